//! Emitters, one file per kind, as Mitsuba 3 lays out `src/emitters/`: an emissive sphere
//! (`sphere.rs`), an emissive triangle of a mesh (`triangle.rs`), an emissive disk (`disk.rs`) or cylinder (`cylinder.rs`), the delta lights `point.rs`,
//! `spot.rs`, `directional.rs` and `projector.rs`, and the environment (`environment.rs`). A kind's Rust file lists its lights in a scene and gives their emitted
//! power; its WGSL file, `shaders/emitters/<kind>.wgsl`, has `sample_<kind>_emitter`,
//! `pdf_<kind>_emitter` and `eval_<kind>_emitter`, and is listed in
//! `shaders::files::EMITTER_KINDS`.
//!
//! `EmitterKind` is the one list a new kind joins. From it come the kinds' numbers
//! (`EMITTER_KIND_*` in WGSL), one `NUM_<KIND>_LIGHTS` override per kind and the kernel's
//! dispatch on a light's kind (`shaders::emitter_dispatch`). The light table holds each kind's
//! lights as one contiguous range, the kinds in this order; which light next event estimation
//! samples is `selection.rs`'s. See the README's "Adding an emitter".

mod cylinder;
mod directional;
mod disk;
mod environment;
mod point;
mod projector;
mod selection;
mod sphere;
mod spot;
mod triangle;

pub use directional::DirectionalLight;
pub use environment::{EnvDistribution, EnvironmentMap, ENVIRONMENT_MAP_HEADER};
pub use point::PointLight;
pub use projector::ProjectorLight;
pub use spot::{light_frame, SpotLight, SpotTexture, BEAM_WIDTH_OF_CUTOFF, DEFAULT_CUTOFF_ANGLE};
pub use selection::{luminance, AliasTable, LUMINANCE_WEIGHTS};

use super::Scene;
use crate::names::named_enum;

named_enum! {
    /// The kind of an emitter (`Light::kind`).
    pub enum EmitterKind("emitter kind") {
        /// An emissive sphere: a diffuse area light, emitting outwards.
        Sphere = "sphere",
        /// An emissive mesh triangle: a diffuse area light, one- or two-sided.
        Triangle = "triangle",
        /// An emissive disk (Mitsuba's `disk`): a diffuse area light, one- or two-sided.
        Disk = "disk",
        /// An emissive cylinder (Mitsuba's `cylinder`): a diffuse area light, one- or two-sided.
        Cylinder = "cylinder",
        /// A point light (Mitsuba's `point`): a delta light.
        Point = "point",
        /// A spot light (Mitsuba's `spot`): a point light with an angular falloff.
        Spot = "spot",
        /// A directional light (Mitsuba's `directional`): a delta light at infinity.
        Directional = "directional",
        /// A projector (Mitsuba's `projector`): a delta light projecting an image.
        Projector = "projector",
        /// The constant environment (Mitsuba's `constant`): radiance from every direction at
        /// infinity.
        Environment = "environment",
    }
}

impl EmitterKind {
    /// The pipeline constant that counts the lights of this kind (`NUM_SPHERE_LIGHTS`), from
    /// its name.
    pub fn count_override(self) -> &'static str {
        static NAMES: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
        &NAMES.get_or_init(|| EmitterKind::ALL.iter().map(|k| format!("NUM_{}_LIGHTS", k.name().to_uppercase())).collect())[self as usize]
    }
}

/// One light: an emitter next event estimation can sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// Index into `Scene::spheres`.
    Sphere(usize),
    /// Triangle `triangle` of `Scene::meshes[mesh]`.
    Triangle { mesh: usize, triangle: usize },
    /// Index into `Scene::quadrics` (a disk).
    Disk(usize),
    /// Index into `Scene::quadrics` (a cylinder).
    Cylinder(usize),
    /// Index into `Scene::point_lights`.
    Point(usize),
    /// Index into `Scene::spot_lights`.
    Spot(usize),
    /// Index into `Scene::directional_lights`.
    Directional(usize),
    /// Index into `Scene::projector_lights`.
    Projector(usize),
    /// The constant environment (`RenderSettings::environment`).
    Environment,
}

impl Light {
    /// Its kind.
    pub fn kind(&self) -> EmitterKind {
        match self {
            Light::Sphere(_) => EmitterKind::Sphere,
            Light::Triangle { .. } => EmitterKind::Triangle,
            Light::Disk(_) => EmitterKind::Disk,
            Light::Cylinder(_) => EmitterKind::Cylinder,
            Light::Point(_) => EmitterKind::Point,
            Light::Spot(_) => EmitterKind::Spot,
            Light::Directional(_) => EmitterKind::Directional,
            Light::Projector(_) => EmitterKind::Projector,
            Light::Environment => EmitterKind::Environment,
        }
    }
}

impl EmitterKind {
    /// Whether its lights are deltas (a point, a direction): BSDF-sampled rays never find them,
    /// so only methods with next event estimation see them.
    pub fn is_delta(self) -> bool {
        matches!(self, EmitterKind::Point | EmitterKind::Spot | EmitterKind::Directional | EmitterKind::Projector)
    }
}

/// The emissive quadrics of `kind` in scene order, each as the light `make` names (the disk and
/// cylinder emitters').
fn emissive_quadrics(scene: &Scene, kind: crate::scene::QuadricKind, make: fn(usize) -> Light) -> Vec<Light> {
    let emits = |q: &crate::scene::Quadric| q.kind == kind && scene.materials[q.material].is_emissive();
    scene.quadrics.iter().enumerate().filter(|(_, q)| emits(q)).map(|(i, _)| make(i)).collect()
}

/// Emitted power of a diffuse area emitter: pi times area times the radiance's luminance, twice
/// that where it emits on both sides.
fn area_emitter_power(area: f64, radiance: glam::DVec3, two_sided: bool) -> f64 {
    let sides = if two_sided { 2.0 } else { 1.0 };
    std::f64::consts::PI * sides * area * luminance(radiance)
}

impl Scene {
    /// The lights of `kind`, in kernel order.
    pub fn lights_of(&self, kind: EmitterKind) -> Vec<Light> {
        match kind {
            EmitterKind::Sphere => sphere::lights(self),
            EmitterKind::Triangle => triangle::lights(self),
            EmitterKind::Disk => disk::lights(self),
            EmitterKind::Cylinder => cylinder::lights(self),
            EmitterKind::Point => point::lights(self),
            EmitterKind::Spot => spot::lights(self),
            EmitterKind::Directional => directional::lights(self),
            EmitterKind::Projector => projector::lights(self),
            EmitterKind::Environment => environment::lights(self),
        }
    }

    /// The lights but the environment (the emissive spheres, every emissive triangle, the emissive disks and cylinders, the point,
    /// spot and directional lights), in kernel order: what next event estimation samples unless
    /// the environment is sampled too. This order fixes which sample dimensions each light uses
    /// when every light is sampled.
    pub fn lights(&self) -> Vec<Light> {
        EmitterKind::ALL.into_iter().filter(|k| *k != EmitterKind::Environment).flat_map(|k| self.lights_of(k)).collect()
    }

    /// The textures its delta lights project (a spot's `texture`, a projector's
    /// `irradiance`), in the order they are packed.
    pub fn light_textures(&self) -> Vec<&crate::scene::Texture> {
        let spots = self.spot_lights.iter().filter_map(|l| l.texture.as_ref().map(|t| &t.texture));
        spots.chain(self.projector_lights.iter().map(|l| &l.irradiance)).collect()
    }

    /// How many delta lights (of the kinds `EmitterKind::is_delta`) the scene has.
    pub fn num_delta_lights(&self) -> usize {
        EmitterKind::ALL.into_iter().filter(|k| k.is_delta()).map(|k| self.lights_of(k).len()).sum()
    }

    /// The first delta light, named for messages ("point light 0"), if any.
    pub fn first_delta_light(&self) -> Option<String> {
        EmitterKind::ALL.into_iter().find(|k| k.is_delta() && !self.lights_of(*k).is_empty()).map(|k| format!("{} light 0", k.name()))
    }

    /// A delta light `method` cannot see, named for messages, where the scene has one and the
    /// method has no next event estimation (only light sampling finds a point or a direction).
    pub fn delta_light_unseen_by(&self, method: &crate::method::Method) -> Option<String> {
        if method.lights != crate::method::LightSampling::None {
            return None;
        }
        self.first_delta_light()
    }

    /// Why `study`, `advise` and `bench` leave `method` out on this scene, if they do: one of
    /// its lights is a delta the method cannot see, or it samples the environment map by the
    /// compensated distribution without MIS (`Method::env_pdf_is_incomplete`).
    pub fn why_left_out(&self, method: &crate::method::Method) -> Option<String> {
        if let Some(light) = self.delta_light_unseen_by(method) {
            return Some(format!("{} is left out: it cannot see {light} (a delta light is found only by next event estimation)", method.name()));
        }
        (self.environment_map.is_some() && method.env_pdf_is_incomplete()).then(|| {
            format!("{} is left out: compensated environment sampling leaves directions to BSDF sampling, which only MIS combines with it", method.name())
        })
    }

    /// The lights next event estimation samples, in kernel order (the light table): the area
    /// lights, then the environment where `sample_environment` and it is not black.
    pub fn sampled_lights(&self, sample_environment: bool) -> Vec<Light> {
        let mut lights = self.lights();
        if sample_environment {
            lights.extend(self.lights_of(EmitterKind::Environment));
        }
        lights
    }

    /// How many lights `lights()` lists, counted without listing them.
    pub fn num_lights(&self) -> usize {
        self.light_spheres().len() + triangle::count(self) + disk::lights(self).len() + cylinder::lights(self).len() + self.num_delta_lights()
    }

    /// Whether any mesh emits.
    pub fn has_triangle_lights(&self) -> bool {
        triangle::count(self) > 0
    }

    /// Whether the environment emits (it is then a light NEE may sample).
    pub fn has_environment(&self) -> bool {
        self.render.environment.max_element() > 0.0 || self.environment_map.as_ref().is_some_and(|m| !m.is_black())
    }

    /// Emitted power of a light, in luminance (the weight of power selection).
    pub fn light_power(&self, light: Light) -> f64 {
        match light {
            Light::Sphere(i) => sphere::power(self, i),
            Light::Triangle { mesh, triangle } => triangle::power(self, mesh, triangle),
            Light::Disk(i) => disk::power(self, i),
            Light::Cylinder(i) => cylinder::power(self, i),
            Light::Point(i) => point::power(self, i),
            Light::Spot(i) => spot::power(self, i),
            Light::Directional(i) => directional::power(self, i),
            Light::Projector(i) => projector::power(self, i),
            Light::Environment => environment::power(self),
        }
    }
}
