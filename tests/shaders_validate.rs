//! naga validates the assembled path tracer for every combination of `override` constants,
//! after specialisation, exactly as the pipelines give it to wgpu (`shaders::specialise`: the
//! constants substituted, the branches they decide pruned) (with the example
//! techniques of `examples/techniques/` spliced in, a light technique for every shape, and
//! switched on in half of them).

use pathlab::gpu::{pipeline_constants, PipelineKey, NO_TRAVERSAL_GUARD};
use pathlab::method::{BsdfSampling, EnvSampling, LightSampling, LightSelect, LobeSelection, Method, MicrofacetSampling, Sampler, TechniqueKind, TechniqueName, TriangleSampling};
use pathlab::scene::Technique;
use pathlab::gpu::SceneFeatures;
use pathlab::shaders;

/// Scene shapes: (spheres, planes, sphere lights, triangles, triangle lights, shading normals,
/// traversal budget, (disks, disk lights, cylinders, cylinder lights)).
const SHAPES: [(u32, u32, u32, u32, u32, bool, u32, (u32, u32, u32, u32)); 4] = [
    (0, 0, 0, 0, 0, false, NO_TRAVERSAL_GUARD, (0, 0, 0, 0)),
    (1, 0, 1, 0, 0, false, NO_TRAVERSAL_GUARD, (1, 1, 0, 0)),
    (4, 4, 2, 0, 0, false, NO_TRAVERSAL_GUARD, (2, 1, 2, 1)),
    (2, 1, 1, 12, 2, true, 1000, (0, 0, 2, 0)),
];

#[test]
fn every_override_permutation_validates() {
    let source = shaders::path_tracer_source();
    // With the example techniques in their kinds' places (compiled in where `on`).
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/techniques");
    let text = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap();
    // A bsdf technique for Phong materials and, of two alphas, microfacet normals.
    let phong_and_caps = ["phong_lobe.wgsl", "ggx_spherical_caps.wgsl"].map(text).join("\n");
    let bsdf = Technique::from_text(TechniqueKind::Bsdf, TechniqueName::new("phong_lobe").unwrap(), dir.join("phong_lobe.wgsl"), &phong_and_caps);
    assert_eq!(bsdf.bsdf_targets(), pathlab::scene::BsdfTargets { phong: true, microfacet: false, microfacet_uv: true });
    // A light technique for every shape: the sphere, triangle, disk and cylinder examples in one
    // file (their functions do not collide).
    let all_shapes = ["sphere_area.wgsl", "triangle_area.wgsl", "quadric_area.wgsl"].map(text).join("\n");
    let light = Technique::from_text(TechniqueKind::Light, TechniqueName::new("sphere_area").unwrap(), dir.join("sphere_area.wgsl"), &all_shapes);
    assert_eq!(light.light_shapes(), pathlab::scene::LightShapes { spheres: true, triangles: true, disks: true, cylinders: true });
    let env = Technique::load(TechniqueKind::Env, dir.join("env_cosine_mix.wgsl")).unwrap();
    let with_techniques = shaders::path_tracer_source_with(12, shaders::TechniqueFiles { bsdf: Some(&bsdf), light: Some(&light), env: Some(&env) });
    // Each source parsed and validated once, then specialised per permutation as the pipelines
    // are (shaders::specialise).
    let parsed = shaders::specialise::parse(&source).unwrap();
    let parsed_with_techniques = shaders::specialise::parse(&with_techniques).unwrap();
    let mut checked = 0;
    for sampler in Sampler::ALL {
        for bsdf in BsdfSampling::ALL {
            for lights in LightSampling::ALL {
                for select in LightSelect::ALL {
                    for triangles in TriangleSampling::ALL {
                        for &(num_spheres, num_planes, num_sphere_lights, num_triangles, triangle_lights, has_shading_normals, budget, (num_disks, num_disk_lights, num_cylinders, num_cylinder_lights)) in &SHAPES {
                            // Specular and environment (shaded, and sampled as a light) on and off together, and the light
                            // interiors with them: each on and each off is compiled once.
                            for on in [false, true] {
                                // Both microfacet strategies and both lobe selections, each with
                                // conductors and plastics on and off.
                                let microfacet = if (checked / 2) % 2 == 0 { MicrofacetSampling::Vndf } else { MicrofacetSampling::Ndf };
                                let lobes = if (checked / 4) % 2 == 0 { LobeSelection::Fresnel } else { LobeSelection::Fixed };
                                // Every environment-map strategy, with the map on and off.
                                let env_sampling = EnvSampling::ALL[(checked / 8) % EnvSampling::ALL.len()];
                                let technique = |name: &str| on.then(|| TechniqueName::new(name).unwrap());
                                let method = Method {
                                    sampler,
                                    bsdf,
                                    lights,
                                    select: Some(select),
                                    triangles,
                                    microfacet,
                                    lobes,
                                    environment: on,
                                    env_sampling,
                                    bsdf_technique: technique("phong_lobe"),
                                    light_technique: technique("sphere_area"),
                                    env_technique: technique("env_cosine_mix"),
                                };
                                let features = SceneFeatures {
                                    num_spheres,
                                    num_planes,
                                    num_disks,
                                    num_cylinders,
                                    // Curve segments with the cylinders.
                                    num_curve_segments: num_cylinders,
                                    num_bspline_segments: num_cylinders,
                                    num_sdf_grids: num_cylinders,
                                    num_sphere_lights,
                                    num_triangle_lights: triangle_lights,
                                    num_disk_lights,
                                    num_cylinder_lights,
                                    // The environment as a light where it is on.
                                    num_environment_lights: on as u32,
                                    // A point, a spot and a directional light where it is on.
                                    num_point_lights: on as u32,
                                    num_spot_lights: on as u32,
                                    num_directional_lights: on as u32,
                                    num_projector_lights: on as u32,
                                    num_triangles,
                                    small_vertices: Default::default(),
                                    has_shading_normals,
                                    has_uvs: on,
                                    // Masks on and off, with uvs on and off.
                                    has_masks: (checked / 3) % 2 == 0,
                                    textured_opacity: on,
                                    // Every kind of texture, or none.
                                    texture_kinds: if on { 31 } else { 0 },
                                    // Each distribution alone, both, or none.
                                    microfacet_distributions: (checked % 4) as u32,
                                    // Every slot of every kind looked up, or none.
                                    textured_slots: [if (checked / 7) % 2 == 0 { u16::MAX } else { 0 }; pathlab::scene::BsdfKind::ALL.len()],
                                    // Back BSDFs on and off, with several kinds and with Phong alone.
                                    has_back_bsdfs: (checked / 5) % 2 == 0,
                                    // Blends on and off, with and without uvs and masks.
                                    has_blends: (checked / 29) % 2 == 0,
                                    // Emission textures with uvs and every texture kind.
                                    has_emission_textures: on && (checked / 31) % 2 == 0,
                                    // Tangent frames and anisotropic microfacets on and off.
                                    anisotropic_roughness: (checked / 11) % 2 == 0,
                                    has_normal_maps: (checked / 13) % 2 == 0,
                                    // Bump maps on and off, with and without normal maps.
                                    has_bump_maps: (checked / 17) % 2 == 0,
                                    rr_depth: if on { 2 } else { 0 },
                                    thin_lens: on,
                                    // Orthographic cameras on and off, with and without a lens.
                                    orthographic: (checked / 19) % 2 == 0,
                                    // Projected light textures on and off.
                                    has_light_textures: (checked / 23) % 2 == 0,
                                    hide_emitters: on,
                                    num_occluding_planes: if on { num_planes } else { 0 },
                                    has_specular: on,
                                    bsdf_kinds: if on { u32::MAX } else { pathlab::scene::BsdfKind::Phong.bit() },
                                    transmitting_kinds: if on { u32::MAX } else { 0 },
                                    has_environment: on,
                                    has_environment_map: on,
                                    light_interiors_reachable: on,
                                    // Power selection stays power (uniform selection is a method of its own).
                                    uniform_light_powers: false,
                                    // Media on and off (two, the camera in one or in none),
                                    // with every light sampling and selection.
                                    num_media: if (checked / 37) % 2 == 0 { 2 } else { 0 },
                                    camera_medium: if (checked / 41) % 2 == 0 { 1 } else { pathlab::shaders::flags::NO_MEDIUM },
                                    // Heterogeneous media's tracking on and off.
                                    max_null_collisions: if (checked / 43) % 2 == 0 { 64 } else { 0 },
                                };
                                // The B-spline segments' searches looped and unrolled; the
                                // stackless traversal's trail in one word and in two.
                                let key = PipelineKey { method, features, traversal_budget: budget, bspline_unrolled: (checked / 47) % 2 == 0, deep_bvh: (checked / 53) % 2 == 0 };
                                let (source, parsed) = if on { (&with_techniques, &parsed_with_techniques) } else { (&source, &parsed) };
                                // Both adapters' tunings (the traversal with and without a stack).
                                let device = if (checked / 16) % 2 == 0 { wgpu::DeviceType::Cpu } else { wgpu::DeviceType::DiscreteGpu };
                                let mut constants = pipeline_constants(&key);
                                constants.extend(pathlab::gpu::AdapterTuning::for_device(device).constants());
                                if let Err(e) = shaders::validate_parsed(parsed, source, &constants) {
                                    panic!("{key:?}:\n{e}");
                                }
                                checked += 1;
                            }
                        }
                    }
                }
            }
        }
    }
    assert_eq!(checked, 4 * 5 * LightSampling::ALL.len() * 3 * 2 * SHAPES.len() * 2);
}

#[test]
fn unknown_constant_is_rejected() {
    // The validation really specialises: a misspelt constant must not pass silently.
    let source = shaders::path_tracer_source();
    assert!(shaders::validate(&source, &[("NO_SUCH_CONSTANT", 1.0)]).is_err());
}
