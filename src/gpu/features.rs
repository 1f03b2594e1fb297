//! The kernel's view of a scene: which features its pipeline is specialised to
//! (`SceneFeatures`, each a WGSL `override` constant) and the order its objects take in the
//! scene buffers (lights first, occluding planes first). The scene itself knows nothing of it.

use crate::accel::SharedVertices;
use crate::scene::{BsdfKind, EmitterKind, QuadricKind, Scene};

/// What a scene requires of the path-tracing kernel; each becomes a WGSL `override` constant,
/// so a pipeline carries only the code its scene uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SceneFeatures {
    pub num_spheres: u32,
    pub num_planes: u32,
    /// Mitsuba's analytic disks and cylinders (`Scene::quadrics`; kernel order `quadric_order`).
    pub num_disks: u32,
    pub num_cylinders: u32,
    /// The segments of Mitsuba's `linearcurve`s (quadrics after the cylinders; never lights).
    pub num_curve_segments: u32,
    /// The segments of Mitsuba's `bsplinecurve`s (quadrics after the linear curves' segments;
    /// never lights).
    pub num_bspline_segments: u32,
    /// Mitsuba's `sdfgrid`s (quadrics after the B-spline segments; never lights).
    pub num_sdf_grids: u32,
    /// Lights of each kind (`EmitterKind`, each a `NUM_<KIND>_LIGHTS` override): the
    /// emissive spheres, the emissive triangles, and the environment where next event
    /// estimation samples it (`PipelineKey::new` decides, by the method).
    pub num_sphere_lights: u32,
    pub num_triangle_lights: u32,
    pub num_disk_lights: u32,
    pub num_cylinder_lights: u32,
    pub num_environment_lights: u32,
    /// The delta lights of each kind (point, spot, directional).
    pub num_point_lights: u32,
    pub num_spot_lights: u32,
    pub num_directional_lights: u32,
    pub num_projector_lights: u32,
    pub num_triangles: u32,
    /// A small scene's distinct vertex positions and each triangle's corners among them
    /// (`accel::SharedVertices`; the default where the scene traverses the BVH), and the
    /// triangles shadow rays test: the `NUM_SMALL_VERTICES`, `SMALL_CORNER_<k>_<j>`,
    /// `SMALL_FIRST_USES_<k>`, `SMALL_SHADOW_TESTS_<k>` and `SMALL_SHADOW_FIRST_USES_<k>`
    /// overrides (`shaders::small_vertex_constants`).
    pub small_vertices: SharedVertices,
    /// Some mesh has vertex normals (interpolated as shading normals), or some SDF grid smooth
    /// normals.
    pub has_shading_normals: bool,
    /// Some material reads the hit's uv parametrisation (`BsdfPlugin::reads_uv`): only then
    /// does the kernel compute it.
    pub has_uvs: bool,
    /// Some material is masked (`Material::opacity`, Mitsuba's `mask`): rays may pass
    /// straight through surfaces.
    pub has_masks: bool,
    /// Some material's opacity is a texture.
    pub textured_opacity: bool,
    /// Per BSDF kind (indexed by its number), the texture slots some material of the kind gives
    /// a texture (`Bsdf::textured_slots`): each kind's `TEXTURED_<KIND>` override. On SIMD CPU
    /// drivers, which run both sides of every branch, a slot looked up for nothing costs a whole
    /// texture lookup.
    pub textured_slots: [u16; crate::scene::BsdfKind::ALL.len()],
    /// The kinds of texture some material uses (bit k: `Texture::kind_number` k): the kernel's
    /// `TEXTURE_KINDS`, so that a scene without grid volumes, say, compiles no grid lookup.
    pub texture_kinds: u32,
    /// The microfacet distributions some material draws normals of (bit 1 << k:
    /// `Distribution::constant` k, Beckmann and GGX): the kernel's `MICROFACET_DISTRIBUTIONS`,
    /// so that a scene of one distribution compiles the other's code out (lavapipe runs both
    /// sides of every branch: every GGX normal paid for Beckmann's visible-normal inversion).
    pub microfacet_distributions: u32,
    /// Some material's roughness differs along u and v (`Bsdf::is_anisotropic`): the kernel's
    /// `ANISOTROPIC_ROUGHNESS` (the anisotropic microfacet formulas) and `HAS_TANGENT_FRAMES`
    /// (hits carry dp/du, which places the lobes).
    pub anisotropic_roughness: bool,
    /// Some material is normal-mapped (`Material::normal_map`, Mitsuba's `normalmap`): the
    /// kernel's `HAS_NORMAL_MAPS`; hits then carry dp/du too (`HAS_TANGENT_FRAMES`).
    pub has_normal_maps: bool,
    /// Some material is bump-mapped (`Material::bump_map`, Mitsuba's `bumpmap`): the kernel's
    /// `HAS_BUMP_MAPS`, which computes the surface's partials dp/du and dp/dv where one is hit
    /// (the bumped normal is a world direction: no tangent frame needed to place it).
    pub has_bump_maps: bool,
    /// Some material has another BSDF on its back (`Material::back`, Mitsuba's `twosided` with
    /// two BSDFs).
    pub has_back_bsdfs: bool,
    /// Some material blends another material's BSDF (`Material::blend`, Mitsuba's `blendbsdf`):
    /// the kernel picks one of the two per vertex.
    pub has_blends: bool,
    /// Some material's emission is a texture (`Material::emission_texture`): the kernel's
    /// `HAS_EMISSION_TEXTURES`, which looks it up where a triangle light is hit or sampled.
    pub has_emission_textures: bool,
    /// Russian roulette from this vertex on; 0: none.
    pub rr_depth: u32,
    /// The camera has a thin lens (`Camera::aperture_radius` > 0).
    pub thin_lens: bool,
    /// The camera is orthographic (`Projection::Orthographic`): parallel camera rays.
    pub orthographic: bool,
    /// Some delta light projects a texture (`SpotLight::texture`): the kernel's
    /// `HAS_LIGHT_TEXTURES`; its kinds count in `texture_kinds`.
    pub has_light_textures: bool,
    /// Mitsuba's `hide_emitters` (`RenderSettings::hide_emitters`).
    pub hide_emitters: bool,
    /// Planes that shadow rays must test (the first ones in kernel order).
    pub num_occluding_planes: u32,
    pub has_specular: bool,
    /// The BSDF kinds some material has (`BsdfKind::bit`): each a `HAS_<KIND>` override.
    pub bsdf_kinds: u32,
    /// The kinds with `TRANSMITS_BY_PARAMETERS` (`BsdfKind::bit`) some material of which
    /// transmits (`Bsdf::transmits`): each a `<STEM>_TRANSMITS` override.
    pub transmitting_kinds: u32,
    pub has_environment: bool,
    /// The environment is an image (`Scene::environment_map`): escaped rays look it up.
    pub has_environment_map: bool,
    /// False when no path vertex can be inside a light: sampling lights from inside (by area)
    /// is compiled out, leaving cone sampling alone.
    pub light_interiors_reachable: bool,
    /// Every light of the table (the environment left out) has the same probability under power
    /// selection, exactly as the kernel reads it (1 / n in f32, each alias slot keeping its own
    /// light): power selection then draws what uniform selection draws, with the same
    /// probability, and the kernel selects uniformly without reading the table
    /// (`pipeline_constants`).
    pub uniform_light_powers: bool,
    /// Participating media (`Scene::media`): the kernel's `NUM_MEDIA`; 0 compiles every
    /// volumetric step out (volpath.wgsl).
    pub num_media: u32,
    /// The medium the camera sits in (`Scene::camera_medium`), `NO_MEDIUM` for none: the
    /// kernel's `CAMERA_MEDIUM`.
    pub camera_medium: u32,
    /// The most null collisions delta or ratio tracking meets along one path segment or shadow
    /// ray in heterogeneous media (`media::max_null_collisions`): the kernel's
    /// `MAX_NULL_COLLISIONS`; 0, without heterogeneous media, compiles tracking out.
    pub max_null_collisions: u32,
}

/// The most area emitters a camera ray passes through under `hide_emitters` (Mitsuba's loop is
/// unbounded; a ray that would cross more sees black, as if the rest were hidden too).
pub const MAX_EMITTER_SKIPS: u32 = 16;

impl SceneFeatures {
    /// Lights of every kind: the light table's length.
    pub fn num_lights(&self) -> u32 {
        EmitterKind::ALL.iter().map(|&k| self.lights_of(k)).sum()
    }

    /// Area emitters a camera ray may have to pass through under `hide_emitters` before it
    /// meets something else, at most: each light sphere twice (in and out), each emissive
    /// triangle and disk once, each light cylinder twice, never more than `MAX_EMITTER_SKIPS`; 0 without `hide_emitters`.
    pub fn emitter_skips(&self) -> u32 {
        if !self.hide_emitters {
            return 0;
        }
        (2 * self.num_sphere_lights + self.num_triangle_lights + self.num_disk_lights + 2 * self.num_cylinder_lights).min(MAX_EMITTER_SKIPS)
    }

    /// Lights of `kind`.
    pub fn lights_of(&self, kind: EmitterKind) -> u32 {
        match kind {
            EmitterKind::Sphere => self.num_sphere_lights,
            EmitterKind::Triangle => self.num_triangle_lights,
            EmitterKind::Disk => self.num_disk_lights,
            EmitterKind::Cylinder => self.num_cylinder_lights,
            EmitterKind::Point => self.num_point_lights,
            EmitterKind::Spot => self.num_spot_lights,
            EmitterKind::Directional => self.num_directional_lights,
            EmitterKind::Projector => self.num_projector_lights,
            EmitterKind::Environment => self.num_environment_lights,
        }
    }

    /// The features a pipeline must support to render `scene`.
    pub fn of(scene: &Scene) -> SceneFeatures {
        SceneFeatures {
            num_spheres: scene.spheres.len() as u32,
            num_planes: scene.planes.len() as u32,
            num_disks: scene.quadrics.iter().filter(|q| q.kind == QuadricKind::Disk).count() as u32,
            num_cylinders: scene.quadrics.iter().filter(|q| q.kind == QuadricKind::Cylinder).count() as u32,
            num_curve_segments: scene.quadrics.iter().filter(|q| q.kind == QuadricKind::CurveSegment).count() as u32,
            num_bspline_segments: scene.quadrics.iter().filter(|q| q.kind == QuadricKind::BsplineSegment).count() as u32,
            num_sdf_grids: scene.quadrics.iter().filter(|q| q.kind == QuadricKind::SdfGrid).count() as u32,
            num_sphere_lights: scene.lights_of(EmitterKind::Sphere).len() as u32,
            num_triangle_lights: scene.lights_of(EmitterKind::Triangle).len() as u32,
            num_disk_lights: scene.lights_of(EmitterKind::Disk).len() as u32,
            num_cylinder_lights: scene.lights_of(EmitterKind::Cylinder).len() as u32,
            num_environment_lights: scene.lights_of(EmitterKind::Environment).len() as u32,
            num_point_lights: scene.point_lights.len() as u32,
            num_spot_lights: scene.spot_lights.len() as u32,
            num_directional_lights: scene.directional_lights.len() as u32,
            num_projector_lights: scene.projector_lights.len() as u32,
            num_triangles: scene.num_triangles() as u32,
            small_vertices: if scene.num_triangles() <= crate::accel::BRUTE_FORCE_TRIANGLES as usize {
                // The kernel's order of the triangles (the BVH's leaves): cheap at this size.
                // Shadow rays skip the faces of the scene's hull and of closed convex meshes
                // turned away from every light (`Scene::shadow_tests_of`); rays that look for the
                // nearest hit test one of each pair of opposite faces of closed convex solids
                // (`Scene::front_face_pairs`).
                let packed = super::PackedTriangles::new(scene, false);
                let corners = packed.corners();
                packed.shared_vertices().map_or(SharedVertices::default(), |(s, _)| {
                    s.with_shadow_tests(scene.shadow_tests_of(&corners)).with_pairs(&scene.front_face_pairs(&corners, &packed.materials()))
                })
            } else {
                SharedVertices::default()
            },
            has_shading_normals: scene.meshes.iter().any(|m| !m.normals.is_empty()) || scene.quadrics.iter().any(|q| q.grid().is_some_and(|g| g.smooth)),
            has_uvs: scene.materials.iter().any(|m| m.reads_uv()),
            has_masks: scene.materials.iter().any(|m| m.opacity.is_some()),
            textured_opacity: scene.materials.iter().any(|m| m.opacity.as_ref().is_some_and(|o| o.texture().is_some())),
            textured_slots: scene.materials.iter().fold([0; crate::scene::BsdfKind::ALL.len()], |mut bits, m| {
                bits[m.bsdf_kind().constant() as usize] |= m.bsdf.textured_slots();
                bits
            }),
            texture_kinds: scene
                .materials
                .iter()
                .flat_map(|m| m.textures())
                .chain(scene.light_textures())
                .fold(0, |kinds, t| kinds | 1 << t.kind_number())
                | scene.media.iter().flat_map(|m| m.textures()).fold(0, |kinds, t| kinds | 1 << t.kind_number()),
            microfacet_distributions: scene.materials.iter().filter_map(|m| m.bsdf.microfacet_distribution()).fold(0, |bits, d| bits | 1 << d.constant()),
            anisotropic_roughness: scene.materials.iter().any(|m| m.bsdf.is_anisotropic()),
            has_normal_maps: scene.materials.iter().any(|m| m.normal_map.is_some()),
            has_bump_maps: scene.materials.iter().any(|m| m.bump_map.is_some()),
            has_back_bsdfs: scene.materials.iter().any(|m| m.back.is_some()),
            has_blends: scene.materials.iter().any(|m| m.blend.is_some()),
            has_emission_textures: scene.materials.iter().any(|m| m.emission_texture.is_some()),
            rr_depth: scene.render.rr_depth.unwrap_or(0),
            thin_lens: scene.camera.aperture_radius > 0.0,
            orthographic: matches!(scene.camera.projection, crate::scene::Projection::Orthographic { .. }),
            has_light_textures: !scene.light_textures().is_empty(),
            hide_emitters: scene.render.hide_emitters,
            has_specular: scene.materials.iter().any(|m| m.bsdf.as_phong().is_some_and(|p| p.specular.max_element() > 0.0)),
            bsdf_kinds: scene.materials.iter().fold(0, |kinds, m| kinds | m.bsdf_kind().bit()),
            transmitting_kinds: scene.materials.iter().filter(|m| m.bsdf.transmits()).fold(0, |kinds, m| kinds | m.bsdf_kind().bit()),
            has_environment: scene.has_environment(),
            has_environment_map: scene.environment_map.is_some(),
            num_occluding_planes: scene.occluding_planes().len() as u32,
            light_interiors_reachable: scene.light_interiors_reachable(),
            uniform_light_powers: scene.light_selection(false).1.draws_uniformly_in_f32(),
            num_media: scene.media.len() as u32,
            camera_medium: scene.camera_medium.map_or(crate::shaders::flags::NO_MEDIUM, |m| m as u32),
            max_null_collisions: crate::scene::media::max_null_collisions(&scene.media),
        }
    }

    /// Every optional feature on (specular lobe, environment lookups, shadow tests of every
    /// plane, light sampling from inside), the object counts kept: the kernel a scene gets
    /// without specialisation, for comparisons. It renders the same image, more slowly.
    pub fn all_on(self) -> SceneFeatures {
        SceneFeatures {
            has_specular: true,
            // Every kind that only reflects; a transmitting kind only where the scene has one:
            // compiling transmission in refines sphere hit points, which changes the image's
            // rounding.
            bsdf_kinds: BsdfKind::ALL.iter().filter(|k| !k.transmits()).fold(self.bsdf_kinds, |kinds, k| kinds | k.bit()),
            has_environment: true,
            microfacet_distributions: 3,
            num_occluding_planes: self.num_planes,
            small_vertices: self.small_vertices.with_shadow_tests(u64::MAX).with_pairs(&[]),
            light_interiors_reachable: true,
            uniform_light_powers: false,
            ..self
        }
    }
}

/// Order of the spheres in the kernel: the lights first (in scene order), so that light l
/// is sphere l, then the others.
pub fn sphere_order(scene: &Scene) -> Vec<usize> {
    let lights = scene.light_spheres();
    let others = (0..scene.spheres.len()).filter(|i| !lights.contains(i));
    lights.iter().copied().chain(others).collect()
}

/// Order of the quadrics in the kernel: the disks, then the cylinders, then the linear curves'
/// segments, the B-spline segments, the SDF grids (validation lists them so), each kind's lights first (in scene order): disk light l is
/// quadric l, cylinder light l quadric NUM_DISKS + l.
pub fn quadric_order(scene: &Scene) -> Vec<usize> {
    let emits = |i: usize| scene.materials[scene.quadrics[i].material].is_emissive();
    let of = |kind: QuadricKind| (0..scene.quadrics.len()).filter(move |&i| scene.quadrics[i].kind == kind);
    [QuadricKind::Disk, QuadricKind::Cylinder, QuadricKind::CurveSegment, QuadricKind::BsplineSegment, QuadricKind::SdfGrid].into_iter().flat_map(|kind| of(kind).filter(|&i| emits(i)).chain(of(kind).filter(|&i| !emits(i)))).collect()
}

/// Order of the planes in the kernel: `Scene::occluding_planes` first, then the others.
pub fn plane_order(scene: &Scene) -> Vec<usize> {
    let occluding = scene.occluding_planes();
    let others = (0..scene.planes.len()).filter(|i| !occluding.contains(i));
    occluding.iter().copied().chain(others).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lights_and_occluding_planes_come_first_in_kernel_order() {
        let text = "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 90\n\
             [render]\nwidth = 8\nheight = 8\nmax_depth = 2\n\
             [materials.lamp]\nemission = 1\n[materials.grey]\ndiffuse = 0.5\n\
             [[spheres]]\ncenter = [0, 0, -5]\nradius = 1\nmaterial = \"lamp\"\n\
             [[spheres]]\ncenter = [3, 0, -5]\nradius = 1\nmaterial = \"grey\"\n\
             [[spheres]]\ncenter = [-3, 0, -5]\nradius = 1\nmaterial = \"lamp\"\n\
             [[planes]]\npoint = [0, -2, 0]\nnormal = [0, 1, 0]\nmaterial = \"grey\"\n\
             [[planes]]\npoint = [0, 0, -3]\nnormal = [0, 0, 1]\nmaterial = \"grey\"\n";
        let s = Scene::parse(text, "test.toml").unwrap();
        // Spheres 0 and 2 emit: they become kernel spheres 0 and 1.
        assert_eq!(sphere_order(&s), vec![0, 2, 1]);
        // The wall between camera and lights can occlude them: it comes first.
        assert_eq!(plane_order(&s), vec![1, 0]);
        let f = SceneFeatures::of(&s);
        assert_eq!((f.num_spheres, f.num_sphere_lights, f.num_lights(), f.num_occluding_planes), (3, 2, 2, 1));
        // Two lamps of one size and emission: power selection is uniform selection.
        assert!(f.uniform_light_powers);
        let s = Scene::parse(&text.replace("[-3, 0, -5]\nradius = 1", "[-3, 0, -5]\nradius = 1.5"), "test.toml").unwrap();
        assert!(!SceneFeatures::of(&s).uniform_light_powers);
    }

    #[test]
    fn power_selection_over_equal_lights_compiles_as_uniform_selection() {
        use crate::method::{LightSelect, Method};
        let s = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/cornell_box.toml")).unwrap();
        let f = SceneFeatures::of(&s);
        assert!(f.uniform_light_powers, "the Cornell box's light: two triangles of one rectangle");
        let select = |name: &str| {
            let key = crate::gpu::PipelineKey::new(Method::from_name(name).unwrap(), f, s.default_light_select());
            crate::gpu::pipeline::pipeline_constants(&key).into_iter().find(|(n, _)| *n == "LIGHT_SELECT").unwrap().1
        };
        assert_eq!(select("mis"), LightSelect::Uniform.constant() as f64);
        assert_eq!(select("mis+power"), LightSelect::Uniform.constant() as f64);
        assert_eq!(select("mis+all"), LightSelect::All.constant() as f64);
    }
}
