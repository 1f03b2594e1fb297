//! Checkpoints: a render saved to an accumulator file, restored into a fresh renderer and
//! continued equals an uninterrupted render bit for bit, for every sampler (Halton and Sobol'
//! index samples globally, so the continuation must start at the right sample index). A
//! checkpoint of another scene, method, seed or size is refused naming the field.

use crate::common;

use std::sync::atomic::AtomicBool;
use std::time::Duration;

use common::*;
use pathlab::method::{Method, Preset, Sampler};
use pathlab::render::{render_checkpointed, Checkpoint, CheckpointError, CheckpointKey, CheckpointPlan, Renderer, Resume};

fn plan(path: &std::path::Path) -> CheckpointPlan {
    CheckpointPlan { path: path.to_path_buf(), every: Duration::from_secs(3600), resume: Resume::IfPresent, planned_total: None }
}

fn key(scene: &pathlab::scene::Scene, method: Method, seed: u32) -> CheckpointKey {
    CheckpointKey {
        scene_hash: scene.content_hash(),
        method,
        seed,
        width: scene.render.width,
        height: scene.render.height,
        max_depth: scene.render.max_depth,
        rr_depth: scene.render.rr_depth,
        techniques: String::new(),
    }
}

fn small_study() -> pathlab::scene::Scene {
    let mut scene = study_scene();
    scene.render.width = 24;
    scene.render.height = 12;
    scene
}

#[test]
fn restored_render_equals_an_uninterrupted_one_for_every_sampler() {
    let scene = small_study();
    let dir = tempfile::tempdir().unwrap();
    for sampler in Sampler::ALL {
        let method = Method { sampler, ..Preset::Mis.method() };
        let whole = render(&scene, method, 37, 9);
        let path = dir.path().join(format!("{}.exr", sampler.name()));
        // First session: 13 spp, saved.
        let mut first = Renderer::new(gpu(), pipelines(), &scene, method, 9).unwrap();
        let (saved, interrupted) =
            render_checkpointed(&mut first, &key(&scene, method, 9), 13, &plan(&path), &AtomicBool::new(false), |_| {}).unwrap();
        assert!(!interrupted);
        assert_eq!(saved.spp, 13);
        let reread = Checkpoint::read(&path).unwrap();
        assert_eq!(reread.pixels, saved.pixels, "{}: the file holds the accumulators exactly", sampler.name());
        // Second session: continue to 37 spp from the file.
        let mut second = Renderer::new(gpu(), pipelines(), &scene, method, 9).unwrap();
        let (done, _) =
            render_checkpointed(&mut second, &key(&scene, method, 9), 37, &plan(&path), &AtomicBool::new(false), |_| {}).unwrap();
        assert_eq!(done.spp, 37);
        assert_eq!(bits(&done.film()), bits(&whole), "{}: resumed != uninterrupted", sampler.name());
        assert_eq!(bits(&second.readback().unwrap().film), bits(&whole));
    }
}

#[test]
fn a_checkpoint_of_another_render_is_refused_naming_the_field() {
    let scene = small_study();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ck.exr");
    let method = Preset::Nee.method();
    let mut r = Renderer::new(gpu(), pipelines(), &scene, method, 1).unwrap();
    render_checkpointed(&mut r, &key(&scene, method, 1), 2, &plan(&path), &AtomicBool::new(false), |_| {}).unwrap();
    let attempt = |k: CheckpointKey| {
        let mut r = Renderer::new(gpu(), pipelines(), &scene, k.method, k.seed).unwrap();
        match render_checkpointed(&mut r, &k, 4, &plan(&path), &AtomicBool::new(false), |_| {}) {
            Err(CheckpointError::Mismatch { field, .. }) => field,
            other => panic!("expected a mismatch, got {other:?}"),
        }
    };
    assert_eq!(attempt(CheckpointKey { seed: 2, ..key(&scene, method, 1) }), "seed");
    assert_eq!(attempt(key(&scene, Preset::Mis.method(), 1)), "bsdf");
    assert_eq!(attempt(CheckpointKey { scene_hash: "0123".into(), ..key(&scene, method, 1) }), "scene_hash");
    // A truncated file is refused as unreadable, never half-used.
    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
    assert!(matches!(Checkpoint::read(&path), Err(CheckpointError::Invalid { .. })));
}
