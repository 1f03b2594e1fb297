//! Cases with an exact answer: direct views of emitters at max_depth 1, and the precision of
//! the accumulator over a million samples per pixel.

use crate::common;

use common::*;
use pathlab::method::Preset;

const EMITTER_IN_VIEW: &str = r#"
[camera]
position = [0, 0, 0]
look_at = [0, 0, -1]
up = [0, 1, 0]
fov_x = 20
[render]
width = 16
height = 8
max_depth = 1
[materials.light]
diffuse = 0.5
emission = [0.7, 3.25, 11.0]
[materials.floor]
diffuse = 0.8
[[spheres]]
center = [0, 0, -10]
radius = 5
material = "light"
[[planes]]
point = [0, -20, 0]
normal = [0, 1, 0]
material = "floor"
"#;

/// Every camera ray hits the emitter: with max_depth 1 each sample is exactly its emission,
/// so every pixel's mean must equal it exactly, for every preset.
#[test]
fn max_depth_one_sees_exactly_the_emission() {
    let scene = scene(EMITTER_IN_VIEW);
    for preset in Preset::ALL {
        let film = render(&scene, preset.method(), 16, 0);
        for p in &film.mean {
            assert_eq!(*p, [0.7f32, 3.25, 11.0], "{preset:?}");
        }
        assert!(film.variance.iter().flatten().all(|&v| v == 0.0), "{preset:?}: noise in a constant image");
    }
}

/// Looking away from every emitter, at a lit floor, max_depth 1 gives exactly 0.
#[test]
fn max_depth_one_without_emitters_in_view_is_black() {
    let text = EMITTER_IN_VIEW.replace("look_at = [0, 0, -1]", "look_at = [0, -1, 1]");
    let scene = scene(&text);
    for preset in Preset::ALL {
        let film = render(&scene, preset.method(), 8, 0);
        assert!(film.mean.iter().flatten().all(|&c| c == 0.0), "{preset:?}");
    }
    // The same view with two segments is lit: the zero above is not an empty image.
    let mut lit = scene.clone();
    lit.render.max_depth = 2;
    assert!(render(&lit, Preset::Mis.method(), 8, 0).average() > 0.0);
}

/// 10^6 samples of the constant 0.1 (an environment seen directly; 0.1 is not a binary
/// fraction): the compensated accumulator keeps the mean's relative error below 1e-6,
/// where plain f32 summation drifts by ~1e-3.
#[test]
fn accumulator_is_accurate_at_a_million_samples() {
    let text = r#"
[camera]
position = [0, 0, 0]
look_at = [0, 0, -1]
up = [0, 1, 0]
fov_y = 60
[render]
width = 2
height = 2
max_depth = 1
environment = 0.1
"#;
    let scene = scene(text);
    let spp = 1_000_000;
    let film = render(&scene, Preset::Plain.method(), spp, 0);
    assert_eq!(film.spp, spp);
    let exact = 0.1f32 as f64;
    for p in &film.mean {
        for &c in p {
            let rel = ((c as f64) - exact).abs() / exact;
            assert!(rel < 1e-6, "relative error {rel:e} of the mean after 10^6 samples");
        }
    }
}

/// The kernel's ray counter, where the count is known exactly: with max_depth 1 one camera ray
/// per sample; inside a closed diffuse sphere with cosine sampling (every direction scatters
/// and hits the sphere) one ray per segment; adding NEE towards the sphere itself (an
/// emitter, sampled by area from inside) one shadow ray per scattering vertex, as every such
/// sample contributes.
#[test]
fn ray_counter_counts_every_ray_traced() {
    use pathlab::method::{LightSampling, Method};
    use pathlab::render::Renderer;
    let count = |scene: &pathlab::scene::Scene, method: Method, spp: u64| {
        finish(Renderer::new(gpu(), pipelines(), scene, method, 0).expect("renderer"), spp).rays
    };
    let view = scene(EMITTER_IN_VIEW);
    let samples = 16 * 8 * 5;
    for preset in Preset::ALL {
        assert_eq!(count(&view, preset.method(), 5), samples, "{preset:?}");
    }
    let shell = scene(
        "[camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, -1]\nup = [0, 1, 0]\nfov_x = 60\n\
         [render]\nwidth = 8\nheight = 8\nmax_depth = 4\n\
         [materials.shell]\ndiffuse = 0.5\nemission = 0.5\n\
         [[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"shell\"\n",
    );
    let samples = 8 * 8 * 3;
    let cosine = Method { lights: LightSampling::None, ..Preset::Cosine.method() };
    assert_eq!(count(&shell, cosine, 3), 4 * samples, "cosine: 4 segments");
    let nee = Method { lights: LightSampling::Nee, ..Preset::Cosine.method() };
    assert_eq!(count(&shell, nee, 3), (4 + 3) * samples, "nee: 4 segments and 3 shadow rays");
}
