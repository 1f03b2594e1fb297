//! Shared helpers of the integration tests: one GPU device and pipeline cache per test binary.
#![allow(dead_code)]

use std::sync::atomic::AtomicBool;
use std::sync::OnceLock;

use pathlab::gpu::{Gpu, PathTracerPipelines};
use pathlab::method::Method;
use pathlab::render::{Budget, Readback, Renderer};
use pathlab::film::Film;
use pathlab::scene::Scene;

pub fn gpu() -> &'static Gpu {
    static GPU: OnceLock<Gpu> = OnceLock::new();
    GPU.get_or_init(|| Gpu::new(None).expect("a Vulkan adapter (lavapipe in CI)"))
}

pub fn pipelines() -> &'static PathTracerPipelines {
    static PIPELINES: OnceLock<PathTracerPipelines> = OnceLock::new();
    PIPELINES.get_or_init(|| PathTracerPipelines::new(&gpu().device))
}

pub fn scene(text: &str) -> Scene {
    Scene::parse(text, "test.toml").unwrap_or_else(|e| panic!("test scene is invalid:\n{e}"))
}

pub fn study_scene() -> Scene {
    Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/study.toml")).expect("study scene")
}

/// Renders `spp` samples per pixel in one call.
pub fn render(scene: &Scene, method: Method, spp: u64, seed: u32) -> Film {
    let r = Renderer::new(gpu(), pipelines(), scene, method, seed).expect("renderer");
    finish(r, spp).film
}

/// Renders `spp` samples per pixel with `renderer` and reads back film and ray count.
pub fn finish(mut renderer: Renderer, spp: u64) -> Readback {
    renderer.render(Budget::Samples(spp), &AtomicBool::new(false), |_| {}).expect("render");
    renderer.readback().expect("readback")
}

/// Bit patterns of every mean and variance value, for exact comparisons.
pub fn bits(film: &Film) -> Vec<u32> {
    film.mean.iter().chain(&film.variance).flatten().map(|x| x.to_bits()).collect()
}

use pathlab::method::{Preset, Sampler};

/// Every unbiased method the suite holds to the contract: the presets, `mis` with the balance
/// heuristic, and `mis` with each sampler.
pub fn unbiased_methods() -> Vec<(String, Method)> {
    let mut methods: Vec<(String, Method)> = Preset::ALL.iter().map(|p| (p.name().to_string(), p.method())).collect();
    let balance = Method { lights: pathlab::method::LightSampling::MisBalance, ..Preset::Mis.method() };
    methods.push((balance.name(), balance));
    for sampler in Sampler::ALL {
        let m = Method { sampler, ..Preset::Mis.method() };
        if !methods.iter().any(|(_, x)| *x == m) {
            methods.push((format!("mis+{}", sampler.name()), m));
        }
    }
    methods
}

/// The two deliberately biased demonstration methods.
pub fn biased_methods() -> Vec<(String, Method)> {
    pathlab::method::biased_demonstrations().into_iter().map(|(n, m)| (n.to_string(), m)).collect()
}

/// A film of the constant `value` with zero variance, as a reference for z-tests.
pub fn constant_film(width: u32, height: u32, value: f32) -> Film {
    let n = (width * height) as usize;
    Film { width, height, spp: u64::MAX, mean: vec![[value; 3]; n], variance: vec![[0.0; 3]; n] }
}

/// Says that a test did not run, and why, where `cargo test` shows it to the user: straight to
/// the process's stderr, past the test harness's output capture (which would hide it, and show
/// the test as passed). The test itself then passes having run nothing, so CI refuses to skip
/// (the callers assert `CI` is unset).
pub fn not_run(test: &str, why: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "\n    NOT RUN: {test}: {why}\n");
}

/// Every unbiased preset, and each preset that samples lights with every light selection and
/// triangle sampling, and `mis` with the balance heuristic: the methods a scene with triangle
/// lights is held to.
pub fn triangle_light_methods() -> Vec<Method> {
    use pathlab::method::{LightSampling, LightSelect, TriangleSampling};
    let mut methods = Vec::new();
    for preset in Preset::ALL {
        let base = preset.method();
        if base.lights == LightSampling::None {
            methods.push(base);
            continue;
        }
        for select in LightSelect::ALL {
            for triangles in TriangleSampling::ALL {
                methods.push(Method { select: Some(select), triangles, ..base });
            }
        }
    }
    methods.push(Method { lights: LightSampling::MisBalance, ..Preset::Mis.method() });
    methods
}
