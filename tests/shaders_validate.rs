//! naga validates the assembled path tracer for every combination of `override` constants,
//! after specialisation, exactly as wgpu would at pipeline creation.

use pathlab::gpu::{pipeline_constants, PipelineKey};
use pathlab::method::{BsdfSampling, LightSampling, Method, Sampler};
use pathlab::scene::SceneFeatures;
use pathlab::shaders;

#[test]
fn every_override_permutation_validates() {
    let source = shaders::path_tracer_source();
    let counts = [(0, 0, 0), (1, 0, 1), (4, 4, 2)];
    let mut checked = 0;
    for sampler in Sampler::ALL {
        for bsdf in BsdfSampling::ALL {
            for lights in LightSampling::ALL {
                for &(num_spheres, num_planes, num_lights) in &counts {
                    for has_specular in [false, true] {
                        for (has_environment, light_interiors_reachable) in [(false, false), (true, true)] {
                            let key = PipelineKey {
                                method: Method { sampler, bsdf, lights },
                                features: SceneFeatures {
                                    num_spheres,
                                    num_planes,
                                    num_lights,
                                    num_occluding_planes: if has_specular { num_planes } else { 0 },
                                    has_specular,
                                    has_environment,
                                    light_interiors_reachable,
                                },
                            };
                            if let Err(e) = shaders::validate(&source, &pipeline_constants(&key)) {
                                panic!("{key:?}:\n{e}");
                            }
                            checked += 1;
                        }
                    }
                }
            }
        }
    }
    assert_eq!(checked, 4 * 5 * 4 * 3 * 2 * 2);
}

#[test]
fn unknown_constant_is_rejected() {
    // The validation really specialises: a misspelt constant must not pass silently.
    let source = shaders::path_tracer_source();
    assert!(shaders::validate(&source, &[("NO_SUCH_CONSTANT", 1.0)]).is_err());
}
