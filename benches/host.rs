//! Criterion benchmarks of the host-side hot spots (`cargo bench`): scene loading and
//! validation, and the end of a render, reading the accumulators back and writing the EXR,
//! at 1024x512. The readback benchmarks need a Vulkan adapter (lavapipe will do).

use std::hint::black_box;
use std::sync::atomic::AtomicBool;

use criterion::{criterion_group, criterion_main, Criterion};

use pathlab::gpu::{Gpu, PathTracerPipelines};
use pathlab::method::Preset;
use pathlab::output::{write_exr, Metadata};
use pathlab::render::{Budget, Renderer};
use pathlab::scene::Scene;

const STUDY: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/study.toml");

fn scene_loading(c: &mut Criterion) {
    c.bench_function("scene load + validation (study.toml)", |b| b.iter(|| Scene::load(black_box(STUDY)).expect("study scene")));
    let text = std::fs::read_to_string(STUDY).expect("study scene");
    c.bench_function("scene validation only (study.toml, in memory)", |b| {
        b.iter(|| Scene::parse(black_box(&text), "study.toml").expect("study scene"))
    });
}

fn readback_and_exr(c: &mut Criterion) {
    let gpu = match Gpu::new(None) {
        Ok(gpu) => gpu,
        Err(e) => {
            eprintln!("skipping readback benchmarks: {e}");
            return;
        }
    };
    let pipelines = PathTracerPipelines::new(&gpu.device);
    let mut scene = Scene::load(STUDY).expect("study scene");
    (scene.render.width, scene.render.height) = (1024, 512);
    let mut renderer = Renderer::new(&gpu, &pipelines, &scene, Preset::Best.method(), 0).expect("renderer");
    renderer.render(Budget::Samples(1), &AtomicBool::new(false), |_| {}).expect("render");
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("bench.exr");
    let metadata = Metadata::new();
    let film = renderer.film().expect("readback");

    c.bench_function("readback 1024x512 (accumulators to mean and variance)", |b| {
        b.iter(|| renderer.readback().expect("readback"))
    });
    c.bench_function("EXR write 1024x512 (RGB)", |b| b.iter(|| write_exr(&path, black_box(&film), &metadata, false).expect("exr")));
    c.bench_function("EXR write 1024x512 (RGB + variance)", |b| {
        b.iter(|| write_exr(&path, black_box(&film), &metadata, true).expect("exr"))
    });
    c.bench_function("readback + EXR write 1024x512", |b| {
        b.iter(|| {
            let film = renderer.film().expect("readback");
            write_exr(&path, &film, &metadata, false).expect("exr")
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = scene_loading, readback_and_exr
}
criterion_main!(benches);
