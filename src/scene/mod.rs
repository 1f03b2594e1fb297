//! Scenes: the TOML format (`raw`), its validation (`validate`), object-to-world transforms
//! (`transform`), triangle meshes from OBJ and PLY files and Mitsuba's built-in shapes (`mesh`),
//! the emitters, one file per kind, in kernel order with their power (`emitters`), the validated model, its identity
//! (`hash`), and which of a method's options can change its image (`ApplicableOptions`).
//!
//! A `Scene` has passed every check: all numbers are finite and in range, every material name
//! resolves, planes do not emit, meshes are in world space with their zero-area triangles
//! dropped. Nothing here touches the GPU.

pub mod bsdfs;
pub mod camera;
mod checker;
mod diagnostic;
pub mod emitters;
pub mod hash;
pub mod image_file;
pub mod media;
pub mod mesh;
pub mod mitsuba;
pub mod overrides;
pub mod quadrics;
mod convex_parts;
mod shadow_hull;
pub mod spectrum;
mod raw;
pub mod technique;
pub mod transform;
pub mod vol_file;
mod validate;

use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::method::{BsdfSampling, LightSampling, Method};

pub mod bsdf_data;
pub mod textures;
pub use textures::Texture;
pub use bsdfs::{
    Bsdf, BsdfData, BsdfKind, CoatingTables, Conductor, Dielectric, Distribution, Phong, Plastic, PolarizedPlastic, Principled, PrincipledThin, PrincipledWeight, RoughConductor, RoughDielectric, RoughPlastic,
    ThinDielectric, NAMED_CONDUCTORS, ROUGH_PLASTIC_TABLE_RES, NormalMap, BumpMap, Opacity, Roughness, Blend,
};
pub use camera::{Camera, Fov, Projection};
pub use diagnostic::{Diagnostic, SceneError, Severity};
pub use emitters::{AliasTable, DirectionalLight, EmitterKind, EnvDistribution, EnvironmentMap, Light, PointLight, ProjectorLight, SpotLight, SpotTexture};
pub use mesh::Mesh;
pub use quadrics::{Quadric, QuadricData, QuadricKind, MAX_QUADRICS};
pub use overrides::{OverrideError, Overrides, Reframing};
pub use technique::{BsdfTargets, LightShapes, Technique, TechniqueError};
pub use transform::Transform;

// Most objects of each kind a scene may have: the capacities of the kernel's uniform buffers
// (src/gpu/scene_buffers.rs), each within wgpu's default 64 KiB uniform binding. The kernel tests
// every object per ray (there is no acceleration structure), so scenes this large are slow anyway.

/// Most spheres (32 bytes each on the GPU).
pub const MAX_SPHERES: usize = 1024;
/// Most planes (32 bytes each).
pub const MAX_PLANES: usize = 1024;
/// Most materials (112 bytes, seven texels of their texel table, each).
pub const MAX_MATERIALS: usize = 512;
/// Most point, spot, directional and projector lights together (96 bytes each).
pub const MAX_DELTA_LIGHTS: usize = 256;

/// The depth `max_depth = -1` (unbounded, allowed only with Russian roulette) stands for. Paths
/// that survive roulette this long are cut: the energy lost is that of light bounced more than
/// 64 times (under 1e-6 of the image at albedo 0.8), and the kernel's loop stays bounded.
pub const UNBOUNDED_DEPTH: u32 = 64;

/// The `[render]` table.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Number of path segments: 1 = emitters seen directly, 2 = direct lighting, ...
    /// (`max_depth = -1` in a file, unbounded, is `UNBOUNDED_DEPTH`).
    pub max_depth: u32,
    /// Russian roulette from this scattering vertex on (Mitsuba's `rr_depth`: the first vertex
    /// is 1); `None`: none.
    pub rr_depth: Option<u32>,
    /// Radiance of rays that escape the scene.
    pub environment: DVec3,
    /// Default samples per pixel, if the scene gives one.
    pub spp: Option<u64>,
    /// Mitsuba's `hide_emitters`: camera rays pass through every area emitter they meet (to
    /// what lies behind) and see no environment; emitters reached after a bounce are unchanged.
    pub hide_emitters: bool,
}

/// A material: a BSDF of one of the kinds of `bsdfs` (Phong by default), which may emit.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub name: String,
    /// The radiance it emits (a diffuse area light; 0: none), the texture's mean where
    /// `emission_texture` is given.
    pub emission: DVec3,
    /// Mitsuba's area emitter with a textured `radiance`: the radiance at each point of the
    /// surface, looked up at its uv parametrisation. Triangle meshes alone (validation refuses
    /// it on spheres and quadrics); `None`: `emission` everywhere.
    pub emission_texture: Option<Texture>,
    /// False: a one-sided BSDF (Mitsuba's default), black seen from behind: from the side its
    /// surface's normal points away from (a sphere's inside, a plane's back, a triangle's back
    /// by its winding). Emission is not affected (see `Mesh::two_sided_emission`).
    pub two_sided: bool,
    pub bsdf: Bsdf,
    /// Mitsuba's `mask` around the BSDF (`bsdfs::Opacity`): the probability that a ray meeting
    /// the surface scatters off it rather than passing straight through; `None`: opaque.
    pub opacity: Option<Opacity>,
    /// Mitsuba's `normalmap` around the BSDF (`bsdfs::NormalMap`): the BSDF scatters in the
    /// frame of the map's normals; `None`: in the surface's shading frame.
    pub normal_map: Option<NormalMap>,
    /// Mitsuba's `bumpmap` around the BSDF (`bsdfs::BumpMap`): the BSDF scatters in the frame of
    /// the bumped surface; `None`: in the surface's shading frame. Not with a normal map.
    pub bump_map: Option<BumpMap>,
    /// Mitsuba's `twosided` with two BSDFs: the material (an index into `Scene::materials`)
    /// whose BSDF scatters on this surface's back, in the frame turned to that side; this
    /// material's own BSDF scatters on its front. `None`: one BSDF for both sides (or for the
    /// front alone, where `two_sided` is false).
    pub back: Option<usize>,
    /// Mitsuba's `blendbsdf` (`bsdfs::Blend`): another material whose BSDF is blended with this
    /// one's by a weight, one of the two picked per path vertex; `None`: this BSDF alone.
    pub blend: Option<Blend>,
    /// The media its surface bounds (`media::Medium`, indices into `Scene::media`): `interior`
    /// on the side its normal points away from, `exterior` on the other (Mitsuba's shape
    /// `interior` and `exterior`, pbrt-v4's `MediumInterface`). A ray that crosses a surface
    /// with either takes the medium of the side it enters (`None`: no medium); across a
    /// surface with neither it keeps its own.
    pub interior: Option<usize>,
    pub exterior: Option<usize>,
}

impl Material {
    /// Whether its surface bounds a medium (a ray crossing it changes medium).
    pub fn is_medium_boundary(&self) -> bool {
        self.interior.is_some() || self.exterior.is_some()
    }

    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }

    /// Its textures: its BSDF's parameters', then its opacity's, then its normal map's or bump
    /// map's, its blend weight's, its emission's (a back material's are its own).
    pub fn textures(&self) -> Vec<&Texture> {
        let mut t = self.bsdf.textures();
        t.extend(self.opacity.as_ref().and_then(Opacity::texture));
        t.extend(self.normal_map.as_ref().map(|n| &n.texture));
        t.extend(self.bump_map.as_ref().map(|b| &b.texture));
        t.extend(self.blend.as_ref().and_then(|b| b.weight.texture()));
        t.extend(self.emission_texture.as_ref());
        t
    }

    /// Whether it reads the hit's uv parametrisation (a texture).
    pub fn reads_uv(&self) -> bool {
        self.bsdf.reads_uv()
            || self.opacity.as_ref().is_some_and(|o| o.texture().is_some())
            || self.normal_map.is_some()
            || self.bump_map.is_some()
            || self.blend.as_ref().is_some_and(|b| b.weight.texture().is_some())
            || self.emission_texture.is_some()
    }

    /// The kind of its BSDF (`BsdfKind`, the registry of kinds).
    pub fn bsdf_kind(&self) -> BsdfKind {
        self.bsdf.kind()
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Sphere {
    pub center: DVec3,
    pub radius: f64,
    /// Index into `Scene::materials`.
    pub material: usize,
    /// The sphere's object axes in world space, orthonormal (`Sphere::WORLD_AXES` unless its
    /// Mitsuba `to_world` rotates it or the TOML gives `axes`). They place the uv
    /// parametrisation, Mitsuba's: with `l` the unit direction from the centre in these axes,
    /// u = atan2(l.y, l.x) / 2π (in [0, 1)) and v = acos(l.z) / π.
    pub axes: [DVec3; 3],
}

impl Sphere {
    pub const WORLD_AXES: [DVec3; 3] = [DVec3::X, DVec3::Y, DVec3::Z];

    /// The uv parametrisation at a point `p` of the sphere (Mitsuba's `sphere`): the
    /// spherical angles of the point's direction from the centre in the object axes.
    pub fn uv(&self, p: DVec3) -> [f64; 2] {
        let d = (p - self.center) / self.radius;
        let l = DVec3::new(d.dot(self.axes[0]), d.dot(self.axes[1]), d.dot(self.axes[2]));
        let phi = l.y.atan2(l.x);
        let phi = if phi < 0.0 { phi + std::f64::consts::TAU } else { phi };
        [phi / std::f64::consts::TAU, l.z.clamp(-1.0, 1.0).acos() / std::f64::consts::PI]
    }
}

/// Infinite plane through `point` with unit `normal`.
#[derive(Debug, Clone, PartialEq)]
pub struct Plane {
    pub point: DVec3,
    pub normal: DVec3,
    pub material: usize,
}

impl Plane {
    /// The uv parametrisation at a point `p` of the plane (pathlab's own: Mitsuba has no
    /// infinite plane): p's world coordinates along the plane's tangent frame, the frame of
    /// Duff et al. 2017 ("Building an orthonormal basis, revisited") about the normal that the
    /// kernel's `frame_from_normal` builds.
    pub fn uv(&self, p: DVec3) -> [f64; 2] {
        let n = self.normal;
        let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
        let a = -1.0 / (s + n.z);
        let b = n.x * n.y * a;
        let t = DVec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
        let bitangent = DVec3::new(b, s + n.y * n.y * a, -n.y);
        [p.dot(t), p.dot(bitangent)]
    }
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
    /// Triangle meshes in world space (`[[meshes]]`, `[[rectangles]]`, `[[cubes]]`).
    pub meshes: Vec<Mesh>,
    /// Mitsuba's analytic disks and cylinders (`[[disks]]`, `[[cylinders]]`), disks first.
    pub quadrics: Vec<Quadric>,
    /// The environment as an image (`[environment_map]`, Mitsuba's `envmap`); the constant
    /// `render.environment` is then black.
    pub environment_map: Option<EnvironmentMap>,
    /// Delta lights (`[[point_lights]]`, `[[spot_lights]]`, `[[directional_lights]]`; Mitsuba's
    /// `point`, `spot`, `directional`): found only by next event estimation.
    pub point_lights: Vec<PointLight>,
    pub spot_lights: Vec<SpotLight>,
    pub directional_lights: Vec<DirectionalLight>,
    /// Projectors (`[[projector_lights]]`, Mitsuba's `projector`): delta lights too.
    pub projector_lights: Vec<ProjectorLight>,
    /// Participating media (`[media.<name>]`, Mitsuba's `homogeneous` under `volpath`), which
    /// materials bound (`Material::interior`, `exterior`) and the camera may sit in.
    pub media: Vec<media::Medium>,
    /// The medium the camera sits in (`camera.medium`, Mitsuba's sensor `<medium>`).
    pub camera_medium: Option<usize>,
    /// How images of this scene are shown and scored on screen (`[display]`, default sRGB):
    /// PNG previews, figures and the display-referred metrics. Not part of `content_hash`.
    pub display: crate::display::DisplayTransform,
    /// Findings that do not stop rendering (unused materials, black scenes, ...).
    pub warnings: Vec<Diagnostic>,
    /// Researchers' sampling techniques loaded for this scene (`--technique`), at most one per
    /// name; methods use them by name (`mis+bsdf=NAME`). Not part of `content_hash`: a
    /// technique changes the variance, never the image's expectation.
    pub techniques: Vec<Technique>,
    /// What reading a Mitsuba file did that the scene itself does not show (`pathlab check`
    /// reports it); empty for TOML.
    pub translation: Translation,
}

/// What translating a Mitsuba file did beyond the scene it made.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Translation {
    /// `instance`s of `shapegroup`s, flattened into world-space shapes; `None` where the file
    /// has none.
    pub instancing: Option<Instancing>,
    /// A sensor `to_world` given as a matrix whose axes are orthogonal only to within 1e-4
    /// (matrices printed to 6 digits), made orthonormal by the camera (its view direction kept,
    /// its up made perpendicular to it, its left their cross product): the largest angle, in
    /// radians, by which an axis moved. `None` for a look-at or an exact matrix.
    pub sensor_correction: Option<f64>,
}

/// What a scene's instances were flattened into: how many instances, of how many shape groups,
/// placed how many shapes (each a mesh, rectangle, cube or sphere of the scene).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Instancing {
    pub instances: usize,
    pub groups: usize,
    pub shapes: usize,
}

/// Whether a scene file is Mitsuba XML (by its extension, `.xml`).
pub fn is_mitsuba(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("xml"))
}

impl Scene {
    /// Reads and validates a scene file: pathlab's TOML, or Mitsuba 3's XML (`.xml`).
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        Scene::load_with(path, &[])
    }

    /// `load`, with `$name` values of a Mitsuba scene overriding its `<default>`s (Mitsuba's
    /// `-D name=value`); a TOML scene takes none.
    pub fn load_with(path: impl AsRef<Path>, defines: &[(String, String)]) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        if is_mitsuba(path) {
            return mitsuba::load(path, defines);
        }
        if let Some((name, _)) = defines.first() {
            return Err(SceneError::Invalid(vec![Diagnostic {
                severity: Severity::Error,
                file: path.to_path_buf(),
                line: 0,
                column: 0,
                field: format!("--define {name}"),
                message: "--define applies to Mitsuba XML scenes (.xml) only".into(),
            }]));
        }
        let text = std::fs::read_to_string(path).map_err(|cause| SceneError::Io {
            path: path.to_path_buf(),
            cause,
        })?;
        Scene::parse(&text, path)
    }

    /// Validates scene text; `path` names it in diagnostics.
    pub fn parse(text: &str, path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        validate::parse_and_validate(text, path.as_ref())
    }

    /// The scene's identity: SHA-256 (first 16 hex digits) of the canonical encoding of
    /// everything that determines its image (`hash`: camera, render settings with size and
    /// depth overrides, materials, spheres, planes; not the path, names, comments or the
    /// default spp). Checkpoints, split-render parts and the study's cache are keyed by it.
    pub fn content_hash(&self) -> String {
        hash::content_hash(self)
    }

    /// The method a command uses when none is named: `best`, and under an environment map that
    /// is a light `best+env`, whose next event estimation samples the map by luminance (as
    /// Mitsuba's `path` samples its `envmap`: a bright sky or sun found only by BSDF-sampled rays
    /// leaves an image of fireflies).
    pub fn default_method_name(&self) -> &'static str {
        if self.environment_map.as_ref().is_some_and(|m| !m.is_black()) {
            "best+env"
        } else {
            "best"
        }
    }

    /// The names of the mesh attributes that `mesh_attribute` textures read, sorted: the slots
    /// of the kernel's attribute table (`PackedTriangles::attributes`).
    pub fn mesh_attribute_names(&self) -> Vec<String> {
        let names: std::collections::BTreeSet<String> =
            self.materials.iter().flat_map(|m| m.textures()).filter_map(|t| t.mesh_attribute().map(str::to_string)).collect();
        names.into_iter().collect()
    }

    /// Triangles of all meshes.
    pub fn num_triangles(&self) -> usize {
        self.meshes.iter().map(|m| m.triangles.len()).sum()
    }

    /// Indices of the spheres that emit: the sphere lights.
    pub fn light_spheres(&self) -> Vec<usize> {
        (0..self.spheres.len())
            .filter(|&i| self.materials[self.spheres[i].material].is_emissive())
            .collect()
    }

    /// Planes that can lie between a path vertex and a light. Planes are opaque and infinite,
    /// so every path vertex is on the camera's side of each plane (or on it); a plane with the
    /// camera and every light sphere strictly on the same side cannot block a shadow ray (the
    /// segment from a vertex to a point of the light stays in that half-space). Contact within
    /// a relative 1e-4 counts as crossing.
    pub fn occluding_planes(&self) -> Vec<usize> {
        const MARGIN: f64 = 1e-4;
        let lights = self.light_spheres();
        (0..self.planes.len())
            .filter(|&j| {
                let p = &self.planes[j];
                let side = |x: DVec3| p.normal.dot(x - p.point);
                let camera = side(self.camera.position);
                let scale = self.camera.position.abs().max_element().max(p.point.abs().max_element()).max(1.0);
                // Camera rays leave from a lens or an orthographic rectangle: all of it on one side.
                let origins = self.camera.ray_origin_corners(self.render.width, self.render.height);
                camera.abs() <= MARGIN * scale
                    || origins.iter().any(|&o| side(o) * camera <= 0.0 || side(o).abs() <= MARGIN * scale.max(o.abs().max_element()))
                    || lights.iter().any(|&l| {
                        let s = &self.spheres[l];
                        let d = side(s.center);
                        d * camera <= 0.0 || d.abs() <= s.radius * (1.0 + MARGIN)
                    })
                    // An emissive triangle is on the camera's side if all its vertices are.
                    || self.meshes.iter().filter(|m| self.materials[m.material].is_emissive()).any(|m| {
                        m.positions.iter().any(|&v| {
                            let d = side(v);
                            d * camera <= 0.0 || d.abs() <= MARGIN * scale.max(v.abs().max_element())
                        })
                    })
                    // A disk or cylinder light is on the camera's side if the box around it is.
                    || self.quadrics.iter().filter(|q| self.materials[q.material].is_emissive()).any(|q| {
                        q.box_corners().into_iter().any(|x| {
                            let d = side(x);
                            d * camera <= 0.0 || d.abs() <= MARGIN * scale.max(x.abs().max_element())
                        })
                    })
                    // A point, spot or projector light as a sphere of radius 0.
                    || self.point_lights.iter().map(|l| l.position).chain(self.spot_lights.iter().map(|l| l.position)).chain(self.projector_lights.iter().map(|l| l.position)).any(|x| {
                        let d = side(x);
                        d * camera <= 0.0 || d.abs() <= MARGIN * scale.max(x.abs().max_element())
                    })
                    // A directional light's shadow rays run to infinity against its direction:
                    // they cross the plane unless they head away from it, into the camera's side.
                    || self.directional_lights.iter().any(|l| -l.direction.dot(p.normal) * camera <= MARGIN * camera.abs())
            })
            .collect()
    }

    /// Whether a path vertex can lie inside a light sphere (or on its inner surface). Spheres
    /// are closed and opaque, so paths from a camera outside every light stay outside, unless
    /// another object reaches into a light. Conservative: contact within a relative 1e-4
    /// counts as reaching in.
    pub fn light_interiors_reachable(&self) -> bool {
        const MARGIN: f64 = 1e-4;
        self.light_spheres().into_iter().any(|l| {
            let light = &self.spheres[l];
            let reach = light.radius * (1.0 + MARGIN);
            // Some camera ray leaves from within the light (the box about the origins, by its
            // half-diagonal).
            let origins = self.camera.ray_origin_corners(self.render.width, self.render.height);
            let spread = origins.iter().map(|o| o.distance(self.camera.position)).fold(0.0, f64::max);
            let camera_inside = self.camera.position.distance(light.center) <= reach + spread;
            let sphere_overlaps = self.spheres.iter().enumerate().any(|(i, s)| {
                i != l && s.center.distance(light.center) <= (s.radius + light.radius) * (1.0 + MARGIN)
            });
            let plane_cuts = self.planes.iter().any(|p| p.normal.dot(light.center - p.point).abs() <= reach);
            camera_inside || sphere_overlaps || plane_cuts
        })
    }
}

/// Which of a method's finer options (`select`, `triangles`, `microfacet`, `lobes`,
/// `environment`, `env_sampling`) can change the image of a scene: the viewer offers only these, `render` notes
/// the others once.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ApplicableOptions {
    /// The light selection: next event estimation is on and the scene has more than one light.
    pub light_select: bool,
    /// Triangle-light sampling: light sampling is on and some triangle emits.
    pub triangle_sampling: bool,
    /// Microfacet sampling: the BSDF strategy samples the material and some material is rough
    /// (a rough conductor or dielectric).
    pub microfacet_sampling: bool,
    /// Lobe selection: some material is layered (plastic), whatever the BSDF strategy (its
    /// delta lobe is drawn by its own choice under every one).
    pub lobe_selection: bool,
    /// Sampling the environment: light sampling is on and the environment is not black.
    pub environment_sampling: bool,
    /// How an environment map is sampled (`env_sampling`): the environment is a map, light
    /// sampling is on and the method samples the environment.
    pub env_sampling: bool,
}

impl ApplicableOptions {
    /// What the scene has, whatever the method.
    pub fn of_scene(scene: &Scene) -> ApplicableOptions {
        ApplicableOptions {
            light_select: scene.num_lights() > 1,
            triangle_sampling: scene.has_triangle_lights(),
            microfacet_sampling: scene.materials.iter().any(|m| m.bsdf_kind().has_microfacets()),
            lobe_selection: scene.materials.iter().any(|m| m.bsdf_kind().selects_lobes()),
            environment_sampling: scene.has_environment(),
            env_sampling: scene.has_environment() && scene.environment_map.is_some(),
        }
    }

    /// What can matter with `method` on the scene: light options need light sampling (without
    /// it, emitters are found only by BSDF-sampled rays, weighted 1), microfacet sampling needs
    /// the material's own strategy.
    pub fn with_method(self, method: &Method) -> ApplicableOptions {
        let lights = method.lights != LightSampling::None;
        let material = matches!(method.bsdf, BsdfSampling::Phong | BsdfSampling::PhongLobeOnly);
        ApplicableOptions {
            light_select: self.light_select && lights,
            triangle_sampling: self.triangle_sampling && lights,
            microfacet_sampling: self.microfacet_sampling && material,
            lobe_selection: self.lobe_selection,
            environment_sampling: self.environment_sampling && lights,
            env_sampling: self.env_sampling && lights && method.environment,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The study-like box: camera and light inside, planes all around.
    fn scene_with(extra: &str) -> Scene {
        let text = format!(
            "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 90\n\
             [render]\nwidth = 8\nheight = 8\nmax_depth = 2\n\
             [materials.lamp]\nemission = 1\n[materials.grey]\ndiffuse = 0.5\n\
             [[spheres]]\ncenter = [0, 0, -5]\nradius = 1\nmaterial = \"lamp\"\n\
             [[planes]]\npoint = [0, -2, 0]\nnormal = [0, 1, 0]\nmaterial = \"grey\"\n{extra}"
        );
        Scene::parse(&text, "test.toml").unwrap()
    }

    #[test]
    fn planes_with_camera_and_lights_on_one_side_cannot_occlude() {
        let s = scene_with("");
        assert!(s.occluding_planes().is_empty());
        assert!(!s.light_interiors_reachable());
        // A wall between camera and light must be tested.
        let s = scene_with("[[planes]]\npoint = [0, 0, -3]\nnormal = [0, 0, 1]\nmaterial = \"grey\"\n");
        assert_eq!(s.occluding_planes(), vec![1]);
        assert!(!s.light_interiors_reachable());
    }

    #[test]
    fn a_plane_or_sphere_reaching_into_a_light_makes_its_interior_reachable() {
        let s = scene_with("[[planes]]\npoint = [0, 0, -5.5]\nnormal = [0, 0, 1]\nmaterial = \"grey\"\n");
        assert_eq!(s.occluding_planes(), vec![1]);
        assert!(s.light_interiors_reachable());
        let s = scene_with("[[spheres]]\ncenter = [0, 1.5, -5]\nradius = 1\nmaterial = \"grey\"\n");
        assert!(s.light_interiors_reachable());
        let s = scene_with("[[spheres]]\ncenter = [0, 3, -5]\nradius = 1\nmaterial = \"grey\"\n");
        assert!(!s.light_interiors_reachable());
    }
}

#[cfg(test)]
mod applicable_options {
    use super::*;
    use crate::method::Preset;

    fn scene(name: &str) -> Scene {
        Scene::load(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes").join(name)).unwrap()
    }

    #[test]
    fn options_apply_where_the_scene_has_what_they_sample_and_the_method_samples_it() {
        let mis = Preset::Mis.method();
        // The study scene: two sphere lights, Phong only.
        let study = ApplicableOptions::of_scene(&scene("study.toml"));
        assert_eq!(study, ApplicableOptions { light_select: true, triangle_sampling: false, microfacet_sampling: false, lobe_selection: false, environment_sampling: false, env_sampling: false });
        // The Cornell box: one triangle light (two triangles), no conductor.
        let cornell = ApplicableOptions::of_scene(&scene("cornell_box.toml"));
        assert_eq!(cornell, ApplicableOptions { light_select: true, triangle_sampling: true, microfacet_sampling: false, lobe_selection: false, environment_sampling: false, env_sampling: false });
        // Veach's scene: four sphere lights, rough conductors; microfacet sampling only with the
        // material's own strategy.
        let veach = ApplicableOptions::of_scene(&scene("veach_mis.xml"));
        assert_eq!(veach, ApplicableOptions { light_select: true, triangle_sampling: false, microfacet_sampling: true, lobe_selection: false, environment_sampling: false, env_sampling: false });
        assert_eq!(veach.with_method(&mis), veach);
        assert!(!veach.with_method(&Preset::Nee.method()).microfacet_sampling);
        // Without light sampling the light options cannot matter.
        let plain = cornell.with_method(&Preset::Plain.method());
        assert_eq!(plain, ApplicableOptions { light_select: false, triangle_sampling: false, microfacet_sampling: false, lobe_selection: false, environment_sampling: false, env_sampling: false });
        assert_eq!(cornell.with_method(&Preset::Nee.method()), cornell);
        // An environment map: how it is sampled matters only where the method samples it.
        let envmap = Scene::load(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/envmap/envmap.xml")).unwrap();
        let env = ApplicableOptions::of_scene(&envmap);
        assert!(env.environment_sampling && env.env_sampling);
        assert!(!env.with_method(&mis).env_sampling);
        assert!(env.with_method(&crate::method::Method { environment: true, ..mis }).env_sampling);
    }
}

#[cfg(test)]
mod texture_coordinates {
    use super::*;

    /// UVs reach the scene's meshes: an OBJ's with v flipped unless `flip_tex_coords = false`
    /// (Mitsuba's default and property), a rectangle's by Mitsuba's parametrisation placed with
    /// its vertices; the scene's hash does not change with them (they change no image yet).
    #[test]
    fn texture_coordinates_reach_the_scenes_meshes() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("tri.obj"), "v 0 0 -1\nv 1 0 -1\nv 0 1 -1\nvt 0 0\nvt 1 0.25\nvt 0 1\nf 1/1 2/2 3/3\n").unwrap();
        let scene = |mesh: &str| {
            let text = format!(
                "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 90\n\
                 [render]\nwidth = 8\nheight = 8\nmax_depth = 2\n[materials.grey]\ndiffuse = 0.5\n\
                 [[meshes]]\nfile = \"tri.obj\"\nmaterial = \"grey\"\n{mesh}\n\
                 [[rectangles]]\nmaterial = \"grey\"\ntransform = {{ translate = [0, 0, -3] }}\n"
            );
            let path = dir.path().join("s.toml");
            std::fs::write(&path, text).unwrap();
            Scene::load(&path).unwrap()
        };
        let flipped = scene("");
        assert_eq!(flipped.meshes[0].uvs, vec![[0.0, 1.0], [1.0, 0.75], [0.0, 0.0]]);
        assert_eq!(flipped.meshes[1].uvs, vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        let kept = scene("flip_tex_coords = false");
        assert_eq!(kept.meshes[0].uvs, vec![[0.0, 0.0], [1.0, 0.25], [0.0, 1.0]]);
        assert_eq!(flipped.content_hash(), kept.content_hash());
    }
}
