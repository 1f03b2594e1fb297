//! Scenes: the TOML format (`raw`), its validation (`validate`) and the validated model.
//!
//! A `Scene` has passed every check: all numbers are finite and in range, every material name
//! resolves, planes do not emit. Nothing here touches the GPU.

mod diagnostic;
mod raw;
mod validate;

use std::path::{Path, PathBuf};

use glam::DVec3;

pub use diagnostic::{Diagnostic, SceneError, Severity};

/// Pinhole camera.
#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    pub position: DVec3,
    pub look_at: DVec3,
    pub up: DVec3,
    pub fov: Fov,
}

/// Field of view in degrees, along one image axis; the other follows from the aspect ratio.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fov {
    X(f64),
    Y(f64),
}

/// The `[render]` table.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Number of path segments: 1 = emitters seen directly, 2 = direct lighting, ...
    pub max_depth: u32,
    /// Radiance of rays that escape the scene.
    pub environment: DVec3,
    /// Default samples per pixel, if the scene gives one.
    pub spp: Option<u64>,
}

/// Normalised modified Phong material: f = kd/pi + ks (n+2)/(2 pi) max(0, dot(wi, r))^n.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub name: String,
    pub diffuse: DVec3,
    pub specular: DVec3,
    pub glossiness: f64,
    pub emission: DVec3,
}

impl Material {
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Sphere {
    pub center: DVec3,
    pub radius: f64,
    /// Index into `Scene::materials`.
    pub material: usize,
}

/// Infinite plane through `point` with unit `normal`.
#[derive(Debug, Clone, PartialEq)]
pub struct Plane {
    pub point: DVec3,
    pub normal: DVec3,
    pub material: usize,
}

/// A validated scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The file it was read from (for messages and default output names).
    pub path: PathBuf,
    pub camera: Camera,
    pub render: RenderSettings,
    pub materials: Vec<Material>,
    pub spheres: Vec<Sphere>,
    pub planes: Vec<Plane>,
    /// Findings that do not stop rendering (unused materials, black scenes, ...).
    pub warnings: Vec<Diagnostic>,
}

impl Scene {
    /// Reads and validates a scene file.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Scene::parse(&text, path)
    }

    /// Validates scene text; `path` names it in diagnostics.
    pub fn parse(text: &str, path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        validate::parse_and_validate(text, path.as_ref())
    }

    /// Indices of the spheres that emit: the lights.
    pub fn light_spheres(&self) -> Vec<usize> {
        (0..self.spheres.len())
            .filter(|&i| self.materials[self.spheres[i].material].is_emissive())
            .collect()
    }

    /// The features a pipeline must support to render this scene.
    pub fn features(&self) -> SceneFeatures {
        SceneFeatures {
            num_spheres: self.spheres.len() as u32,
            num_planes: self.planes.len() as u32,
            num_lights: self.light_spheres().len() as u32,
            has_specular: self.materials.iter().any(|m| m.specular.max_element() > 0.0),
            has_environment: self.render.environment.max_element() > 0.0,
        }
    }
}

/// What a scene requires of the path-tracing kernel; each becomes a WGSL `override` constant,
/// so a pipeline carries only the code its scene uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SceneFeatures {
    pub num_spheres: u32,
    pub num_planes: u32,
    pub num_lights: u32,
    pub has_specular: bool,
    pub has_environment: bool,
}
