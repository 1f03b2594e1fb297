//! Shared helpers of the integration tests: one GPU device and pipeline cache per test binary.
#![allow(dead_code)]

use std::sync::atomic::AtomicBool;
use std::sync::OnceLock;

use pathlab::gpu::{Gpu, PathTracerPipelines};
use pathlab::method::Method;
use pathlab::render::{Budget, Film, Renderer};
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
    let mut r = Renderer::new(gpu(), pipelines(), scene, method, seed).expect("renderer");
    r.render(Budget::Samples(spp), &AtomicBool::new(false), |_| {}).expect("render");
    r.film().expect("readback")
}

/// Bit patterns of every mean and variance value, for exact comparisons.
pub fn bits(film: &Film) -> Vec<u32> {
    film.mean.iter().chain(&film.variance).flatten().map(|x| x.to_bits()).collect()
}
