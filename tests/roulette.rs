//! Russian roulette (`render.rr_depth`, `--rr-depth`) leaves every image's expectation as it was.
//!
//! 1. The closed emitting box of tests/mesh_scenes.rs (albedo a, emission e, camera inside):
//!    at depth d every pixel's expectation is L = e (1 - a^d) / (1 - a). With roulette from
//!    vertex 1 or 3, for every light sampling strategy, and with max_depth = -1 (unbounded:
//!    `UNBOUNDED_DEPTH`, L = e (1 - a^64) / (1 - a)), each image mean is z-tested against L.
//! 2. The Cornell box with roulette from vertex 2 against the same scene without it, per pixel
//!    (the suite's two-sample z-test, Šidák-corrected over all channels, at least 99.75% of
//!    channels passing), and with Mitsuba's rr_depth = 5 against Mitsuba's own render (the
//!    fixture of tests/cornell_box.rs, made with rr_depth 5).
//!
//! Each test fails falsely with probability below 0.01. Break: without the division by the
//! survival probability the box's mean falls to 0.350 against 0.498 (z = -540 for mis), and
//! only 42% of the Cornell box's channels pass against no roulette (mean z -7.4).

use crate::common;

use common::*;
use pathlab::method::{LightSampling, Method, Preset};
use pathlab::scene::UNBOUNDED_DEPTH;
use pathlab::stats::{image_mean_and_error, z_test, z_threshold};

const ALBEDO: f64 = 0.5;
const EMISSION: f64 = 0.25;

fn box_scene(max_depth: i64, rr_depth: u32) -> String {
    format!(
        "[camera]\nposition = [0.1, -0.2, 0.3]\nlook_at = [1, 0.5, -2]\nup = [0, 1, 0]\nfov_x = 100\n\
         [render]\nwidth = 16\nheight = 16\nmax_depth = {max_depth}\nrr_depth = {rr_depth}\n\
         [materials.wall]\ndiffuse = {ALBEDO}\nemission = {EMISSION}\n\
         [[cubes]]\nmaterial = \"wall\"\ntwo_sided_emission = true\ntransform = {{ scale = 2 }}\n"
    )
}

#[test]
fn roulette_keeps_the_analytic_radiance_of_the_closed_box() {
    let methods = [
        Preset::Plain.method(),
        Preset::Nee.method(),
        Preset::Mis.method(),
        Method { lights: LightSampling::MisBalance, ..Preset::Mis.method() },
        Preset::Best.method(),
    ];
    let cases: Vec<(i64, u32, u32)> = [(8, 1), (8, 3)]
        .into_iter()
        .flat_map(|(d, rr)| methods.iter().map(move |_| (d, rr, d as u32)))
        .chain([(-1, 2, UNBOUNDED_DEPTH)])
        .collect();
    let threshold = z_threshold(0.01, 3 * cases.len());
    let mut failed = Vec::new();
    for (k, &(max_depth, rr_depth, depth)) in cases.iter().enumerate() {
        let method = if max_depth == -1 { Preset::Mis.method() } else { methods[k % methods.len()] };
        let scene = scene(&box_scene(max_depth, rr_depth));
        assert_eq!((scene.render.max_depth, scene.render.rr_depth), (depth, Some(rr_depth)));
        let expected = EMISSION * (1.0 - ALBEDO.powi(depth as i32)) / (1.0 - ALBEDO);
        let film = render(&scene, method, 256, 300 + k as u32);
        for c in 0..3 {
            let (mean, err) = image_mean_and_error(&film, c);
            let z = (mean - expected) / err.max(1e-12);
            if c == 0 {
                println!("max_depth {max_depth} rr_depth {rr_depth} {}: mean {mean:.5} expected {expected:.5} z {z:+.2}", method.name());
            }
            if !(z.abs() <= threshold) {
                failed.push(format!("max_depth {max_depth} rr_depth {rr_depth} {} channel {c}: mean {mean}, expected {expected}, z {z:.2}", method.name()));
            }
        }
    }
    assert!(failed.is_empty(), "{failed:#?}");
}

fn cornell(rr_depth: Option<u32>, size: u32) -> pathlab::scene::Scene {
    let mut s = pathlab::scene::Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/cornell_box.toml")).unwrap();
    s.render.width = size;
    s.render.height = size;
    s.render.rr_depth = rr_depth;
    s
}

#[test]
fn roulette_agrees_with_the_same_scene_without_it_and_with_mitsuba() {
    const MIN_PASS: f64 = 0.9975;
    let method = Preset::Mis.method();
    let plain = render(&cornell(None, 32), method, 4096, 1);
    let roulette = render(&cornell(Some(2), 32), method, 4096, 2);
    let t = z_test(&plain, &roulette, 0.01 / 2.0);
    println!("rr_depth 2 against none: {:.4} of {} channels pass (|z| <= {:.2}), max |z| {:.2}, mean z {:+.3}", t.pass_fraction, t.channels, t.threshold, t.max_abs_z, t.mean_z);
    assert!(t.pass_fraction >= MIN_PASS, "roulette from vertex 2 differs from no roulette: {t:?}");

    // Mitsuba's fixture (64x64, rr_depth 5, its default) against pathlab with rr_depth 5, on
    // 2x2 blocks as tests/cornell_box.rs tests mis.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/cornell");
    let mean = pathlab::output::read_exr_image(&dir.join("reference.exr")).unwrap().film;
    let var = pathlab::output::read_exr_image(&dir.join("reference_var.exr")).unwrap().film;
    let record: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("reference.json")).unwrap()).unwrap();
    let reference = pathlab::film::Film { spp: record["spp"].as_u64().unwrap(), variance: var.mean, ..mean };
    let film = render(&cornell(Some(5), 64), method, 256, 3);
    let t = z_test(&reference.downsample(2), &film.downsample(2), 0.01 / 2.0);
    println!("rr_depth 5 against Mitsuba: {:.4} of {} channels pass (|z| <= {:.2}), max |z| {:.2}, mean z {:+.3}", t.pass_fraction, t.channels, t.threshold, t.max_abs_z, t.mean_z);
    assert!(t.pass_fraction >= MIN_PASS, "roulette from vertex 5 differs from Mitsuba: {t:?}");
}
