//! A researcher's own WGSL technique (`--technique KIND:FILE.wgsl`): proven or refused before it
//! renders, then rendering the image the built-ins render.
//!
//! The check (`pathlab::technique::check`) is held to the verdicts it must give: the correct
//! examples of `examples/techniques/` are proven on the study scene's configurations (each
//! check's false-refusal probability is at most 0.01, by its Šidák-corrected level, and its
//! seed is fixed), the study's mistake (`phong_n_plus_2.wgsl`) and five techniques broken on
//! purpose (`tests/fixtures/techniques/`) are refused, each for its own reason. The correct
//! examples' renders pass the per-pixel z-test against the built-in `mis` (Mitsuba's
//! `test_renders.py` protocol, as tests/unbiased_study.rs: Šidák-corrected over all channels
//! for alpha = 0.01, at least 99.75% of channels pass), and so fails the study's mistake when
//! rendered anyway (the test's power). A technique that faults (NaN, a loop that never ends)
//! renders without hanging, its faulted samples counted.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common;

use common::*;
use pathlab::chi2::Chi2Failure;
use pathlab::method::{Method, Preset, TechniqueKind};
use pathlab::scene::{Scene, Technique, TechniqueError};
use pathlab::stats::z_test;
use pathlab::technique::{self, CheckOptions, Verdict};

const MIN_PASS: f64 = 0.9975;

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/techniques").join(name)
}

fn broken(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/techniques").join(name)
}

fn check(kind: TechniqueKind, path: &Path) -> Result<Verdict, TechniqueError> {
    let t = Technique::load(kind, path).unwrap();
    technique::check(gpu(), &t, &study_scene(), CheckOptions::default(), |_, _, _| {})
}

/// The failure the refused verdict names first.
fn failure(v: &Verdict) -> &Chi2Failure {
    assert!(!v.passed(), "{}", v.report());
    v.results.iter().find_map(|r| r.failure.as_ref()).unwrap_or_else(|| panic!("no hard failure:\n{}", v.report()))
}

#[test]
fn the_examples_are_proven_and_the_studys_mistake_is_refused() {
    for (kind, file) in [(TechniqueKind::Bsdf, "phong_lobe.wgsl"), (TechniqueKind::Light, "sphere_area.wgsl")] {
        let v = check(kind, &example(file)).unwrap();
        println!("{}", v.report());
        assert!(v.passed(), "{}", v.report());
        assert_eq!(v.results.len(), if kind == TechniqueKind::Bsdf { 18 } else { 8 }, "every configuration ran");
    }
    // (n + 2) for (n + 1): the pdf integrates to 1 + P_s / (n + 1) where the material has a lobe.
    let v = check(TechniqueKind::Bsdf, &example("phong_n_plus_2.wgsl")).unwrap();
    println!("{}", v.report());
    match failure(&v) {
        Chi2Failure::Mass { mass } => assert!(*mass > 1.005, "{mass}"),
        other => panic!("refused for another reason: {other}"),
    }
}

#[test]
fn broken_techniques_are_refused_each_for_its_reason() {
    let v = check(TechniqueKind::Bsdf, &broken("wrong_scale.wgsl")).unwrap();
    assert!(matches!(failure(&v), Chi2Failure::Mass { mass } if (mass - 1.1).abs() < 1e-3), "{}", v.report());

    let v = check(TechniqueKind::Bsdf, &broken("zero_region.wgsl")).unwrap();
    assert!(matches!(failure(&v), Chi2Failure::Uncovered { .. }), "{}", v.report());

    let v = check(TechniqueKind::Bsdf, &broken("nan.wgsl")).unwrap();
    match failure(&v) {
        // sqrt(u - 0.01) is NaN for 1% of the samples.
        Chi2Failure::Faults { count, total, what } => {
            assert!(what.contains("non-finite"), "{what}");
            assert!((*count as f64 / *total as f64 - 0.01).abs() < 1e-3, "{count} of {total}");
        }
        other => panic!("refused for another reason: {other}"),
    }

    let v = check(TechniqueKind::Bsdf, &broken("infinite_loop.wgsl")).unwrap();
    match failure(&v) {
        Chi2Failure::Faults { count, total, what } => {
            assert!(what.contains("loop stopped"), "{what}");
            assert_eq!(count, total);
        }
        other => panic!("refused for another reason: {other}"),
    }

    // Refused by naga before any GPU work, at the file's own line and column.
    match check(TechniqueKind::Bsdf, &broken("syntax_error.wgsl")) {
        Err(TechniqueError::Invalid { message }) => assert!(message.contains("syntax_error.wgsl:6:5: expected `;`"), "{message}"),
        other => panic!("not refused as invalid: {other:?}"),
    }
}

#[test]
fn a_technique_that_breaks_the_contract_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        Technique::load(TechniqueKind::Bsdf, &p).unwrap()
    };
    // A missing function: the contract is quoted.
    let t = write("half.wgsl", "fn sample_bsdf_technique(wo: vec3f, m: PhongMaterial, u: vec2f, u_lobe: f32) -> vec3f { return wo; }\n");
    let e = pathlab::shaders::validate_technique(&t).unwrap_err().to_string();
    assert!(e.contains("half.wgsl: does not fit the contract of a bsdf technique") && e.contains("fn pdf_bsdf_technique(wo: vec3f"), "{e}");
    // State is refused at its line.
    let t = write("stateful.wgsl", "fn pdf_bsdf_technique(wo: vec3f, m: PhongMaterial, wi: vec3f) -> f32 { return 1.0; }\nvar<private> calls: u32;\nfn sample_bsdf_technique(wo: vec3f, m: PhongMaterial, u: vec2f, u_lobe: f32) -> vec3f { return wo; }\n");
    let e = pathlab::shaders::validate_technique(&t).unwrap_err().to_string();
    assert!(e.contains("stateful.wgsl:2:") && e.contains("`calls`"), "{e}");
    // A name that cannot be a method's.
    let p = dir.path().join("my lobe.wgsl");
    std::fs::write(&p, "").unwrap();
    assert!(matches!(Technique::load(TechniqueKind::Bsdf, &p), Err(TechniqueError::Name { .. })));
}

/// The study scene at 32x16 with `techniques` loaded.
fn small_scene(techniques: &[(TechniqueKind, PathBuf)]) -> Scene {
    let mut scene = study_scene();
    scene.render.width = 32;
    scene.render.height = 16;
    scene.techniques = techniques.iter().map(|(k, p)| Technique::load(*k, p).unwrap()).collect();
    scene
}

#[test]
fn the_examples_render_the_built_in_image_and_the_mistake_does_not() {
    let reference_scene = small_scene(&[]);
    let reference = render(&reference_scene, Preset::Mis.method(), 65536, 1234);
    let scene = small_scene(&[
        (TechniqueKind::Bsdf, example("phong_lobe.wgsl")),
        (TechniqueKind::Light, example("sphere_area.wgsl")),
        (TechniqueKind::Bsdf, example("phong_n_plus_2.wgsl")),
    ]);
    let mut report = Vec::new();
    let mut failures = Vec::new();
    // Without light sampling, lights are found by the BSDF's samples alone (the study's
    // `phong`), tested on 4x4-pixel blocks as in tests/unbiased_study.rs: there the mistake's
    // specular weights, (n + 1) / (n + 2) too small, darken the image. Its bias is local (the
    // highlights): at 65536 spp 4 of 96 channels failed (max |z| 3.99 against 3.88), so the
    // pair renders 131072 (7 fail, max |z| 6.24; the control's max |z| 3.61).
    for (name, spp, expect_pass) in [
        ("mis+bsdf=phong_lobe", 16384, true),
        ("mis+light=sphere_area", 16384, true),
        ("mis+bsdf=phong_lobe+light=sphere_area", 16384, true),
        ("phong+bsdf=phong_lobe", 131072, true),
        ("phong+bsdf=phong_n_plus_2", 131072, false),
    ] {
        let method = Method::from_name(name).unwrap();
        let r = pathlab::render::Renderer::new(gpu(), pipelines(), &scene, method, 77).expect("renderer");
        let out = finish(r, spp);
        assert_eq!(out.faults, 0, "{name}: faults");
        let blocks = method.lights == pathlab::method::LightSampling::None;
        let z = if blocks { z_test(&reference.downsample(4), &out.film.downsample(4), 0.01) } else { z_test(&reference, &out.film, 0.01) };
        report.push(format!("{name} ({spp} spp): {:.4} of {} channels pass |z| <= {:.2}; max |z| {:.2}, mean z {:+.3}", z.pass_fraction, z.channels, z.threshold, z.max_abs_z, z.mean_z));
        if (z.pass_fraction >= MIN_PASS) != expect_pass {
            failures.push(name);
        }
    }
    println!("{}", report.join("\n"));
    assert!(failures.is_empty(), "{failures:?}:\n{}", report.join("\n"));
}

#[test]
fn faulting_techniques_render_without_hanging_and_are_counted() {
    let scene = small_scene(&[(TechniqueKind::Bsdf, broken("nan.wgsl")), (TechniqueKind::Light, broken("infinite_loop_light.wgsl"))]);
    for (name, share) in [("mis+bsdf=nan", (0.002, 0.05)), ("nee+light=infinite_loop_light", (0.5, 1.0))] {
        let method = Method::from_name(name).unwrap();
        let r = pathlab::render::Renderer::new(gpu(), pipelines(), &scene, method, 5).expect("renderer");
        let out = finish(r, 16);
        let samples = 32 * 16 * 16;
        let fraction = out.faults as f64 / samples as f64;
        assert!(fraction > share.0 && fraction <= share.1, "{name}: {} faulted samples of {samples}", out.faults);
        assert!(out.film.mean.iter().flatten().all(|x| x.is_finite()), "{name}: a fault poisoned the image");
    }
}

#[test]
fn the_command_line_refuses_a_technique_naming_why_and_records_a_proven_one() {
    let dir = tempfile::tempdir().unwrap();
    let pathlab = || {
        let mut c = Command::new(env!("CARGO_BIN_EXE_pathlab"));
        c.current_dir(dir.path()).env("NO_COLOR", "1");
        c
    };
    let study = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.toml");
    let spec = |kind: &str, p: PathBuf| format!("{kind}:{}", p.display());
    // check-technique: 2 for a refusal, with the reason and the histogram.
    let out = pathlab().args(["check-technique", &spec("bsdf", example("phong_n_plus_2.wgsl"))]).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(2), "{stdout}");
    assert!(stdout.contains("verdict: REFUSED") && stdout.contains("not 1 (a wrongly normalised pdf)"), "{stdout}");
    assert!(dir.path().join("phong_n_plus_2-check.png").exists());
    // The same as JSON: the verdict, the failing configuration and why, the histogram.
    std::fs::remove_file(dir.path().join("phong_n_plus_2-check.png")).unwrap();
    let out = pathlab().args(["check-technique", "--json", &spec("bsdf", example("phong_n_plus_2.wgsl"))]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stdout)));
    assert_eq!(json["technique"], "bsdf:phong_n_plus_2");
    assert_eq!(json["verdict"], "refused");
    let worst = json["worst"].as_str().unwrap();
    let failing = json["configurations"].as_array().unwrap().iter().find(|c| c["name"] == worst).unwrap();
    assert_eq!(failing["passed"], false);
    assert!(failing["failure"].as_str().unwrap().contains("not 1 (a wrongly normalised pdf)"), "{failing}");
    assert_eq!(json["histogram"], "phong_n_plus_2-check.png");
    assert!(dir.path().join("phong_n_plus_2-check.png").exists());
    // render refuses it before rendering, and says how to render it anyway.
    let out = pathlab().args(["render", study.to_str().unwrap(), "--width", "16", "--height", "8", "--spp", "4"]).arg("--technique").arg(spec("bsdf", example("phong_n_plus_2.wgsl"))).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("technique bsdf:phong_n_plus_2 is refused") && stderr.contains("--allow-unproven"), "{stderr}");
    assert!(!dir.path().join("study.exr").exists());
    // A proven one renders, and the header says which code made the image.
    let out = pathlab().args(["render", study.to_str().unwrap(), "--width", "16", "--height", "8", "--spp", "4", "--method", "mis"]).arg("--technique").arg(spec("light", example("sphere_area.wgsl"))).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let (_, meta) = pathlab::output::read_exr(&dir.path().join("study.exr")).unwrap();
    let get = |k: &str| meta.iter().find(|(key, _)| key == k).map(|(_, v)| v.clone()).unwrap_or_else(|| panic!("no {k} in {meta:?}"));
    assert_eq!(get("method"), "mis+light=sphere_area");
    let sha = Technique::load(TechniqueKind::Light, example("sphere_area.wgsl")).unwrap().sha256;
    assert_eq!(get("techniques"), format!("light=sphere_area@{sha}"));
    assert_eq!(get("technique_verdict"), "proven");
    assert_eq!(get("technique_faults"), "0");
}

#[test]
fn a_quick_study_gives_the_technique_its_rows() {
    let dir = tempfile::tempdir().unwrap();
    let study = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.toml");
    let out = Command::new(env!("CARGO_BIN_EXE_pathlab"))
        .args(["study", study.to_str().unwrap(), "--quick", "--quiet", "--methods", "nee,mis", "--spp", "1,16", "--time", "0.1", "--seeds", "1", "--reference-spp", "256"])
        .arg("--out")
        .arg(dir.path().join("s"))
        .arg("--technique")
        .arg(format!("light:{}", example("sphere_area.wgsl").display()))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("technique light:sphere_area: proven"), "{stderr}");
    let report = std::fs::read_to_string(dir.path().join("s/report.md")).unwrap();
    // Beside each method that samples lights, in every table.
    for row in ["| nee+light=sphere_area | 16 |", "| mis+light=sphere_area | 16 |", "| nee+light=sphere_area | 0.1 |", "| mis+light=sphere_area | no bias detected"] {
        assert!(report.contains(row), "no `{row}` in\n{report}");
    }
}

#[test]
fn a_toml_scene_loads_its_techniques_and_names_a_bad_one() {
    let dir = tempfile::tempdir().unwrap();
    let study = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.toml")).unwrap();
    std::fs::copy(example("sphere_area.wgsl"), dir.path().join("sphere_area.wgsl")).unwrap();
    let with = format!("{study}\n[techniques]\nlight = [\"sphere_area.wgsl\"]\n");
    let scene = Scene::parse(&with, dir.path().join("scene.toml")).unwrap();
    assert_eq!(scene.techniques.len(), 1);
    assert_eq!((scene.techniques[0].kind, scene.techniques[0].name.as_str()), (TechniqueKind::Light, "sphere_area"));
    // Not part of the scene's identity: a technique changes the variance, not the image.
    assert_eq!(scene.content_hash(), study_scene().content_hash());
    let bad = format!("{study}\n[techniques]\nbsdf = [\"missing.wgsl\"]\n");
    let line = bad.lines().count();
    let e = Scene::parse(&bad, dir.path().join("scene.toml")).unwrap_err().to_string();
    assert!(e.contains(&format!("scene.toml:{line}:")) && e.contains("techniques.bsdf") && e.contains("missing.wgsl"), "{e}");
}

#[test]
fn faults_survive_shards_and_their_merge() {
    let dir = tempfile::tempdir().unwrap();
    let study = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.toml");
    let nan = format!("bsdf:{}", broken("nan.wgsl").display());
    let run = |extra: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_pathlab"))
            .current_dir(dir.path())
            .args(["render", study.to_str().unwrap(), "--width", "16", "--height", "8", "--spp", "8", "--method", "mis", "--allow-unproven", "--quiet"])
            .args(["--technique", &nan])
            .args(extra)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8_lossy(&out.stderr).to_string()
    };
    let stderr = run(&["-o", "whole.exr"]);
    assert!(stderr.contains("UNPROVEN") && stderr.contains("samples had a technique fault"), "{stderr}");
    run(&["--shard", "0/2", "-o", "a.exr"]);
    run(&["--shard", "1/2", "-o", "b.exr"]);
    let out = Command::new(env!("CARGO_BIN_EXE_pathlab")).current_dir(dir.path()).args(["merge", "a.exr", "b.exr", "-o", "merged.exr"]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let header = |name: &str| pathlab::output::read_exr(&dir.path().join(name)).unwrap();
    let (_, whole_meta) = header("whole.exr");
    let (_, merged_meta) = header("merged.exr");
    let get = |m: &pathlab::output::Metadata, k: &str| m.iter().find(|(key, _)| key == k).map(|(_, v)| v.clone());
    let faults = get(&whole_meta, "technique_faults").unwrap();
    assert!(faults.parse::<u64>().unwrap() > 0);
    assert_eq!(get(&merged_meta, "technique_faults"), Some(faults));
    assert_eq!(get(&merged_meta, "techniques"), get(&whole_meta, "techniques"));
    assert!(get(&whole_meta, "technique_verdict").unwrap().starts_with("UNPROVEN"));
}

#[test]
fn an_environment_technique_is_proven_on_the_map_and_renders_its_image() {
    let envmap = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/envmap/envmap.xml");
    let mut scene = Scene::load(&envmap).unwrap();
    scene.render.width = 24;
    scene.render.height = 24;
    scene.render.max_depth = 3;
    let mix = Technique::load(TechniqueKind::Env, example("env_cosine_mix.wgsl")).unwrap();
    let v = technique::check(gpu(), &mix, &scene, CheckOptions::default(), |_, _, _| {}).unwrap();
    println!("{}", v.report());
    assert!(v.passed() && v.results.len() == 3, "{}", v.report());
    // The cosine alone never draws below the surface, where the map is not black.
    let only = Technique::load(TechniqueKind::Env, broken("env_cosine_only.wgsl")).unwrap();
    let v = technique::check(gpu(), &only, &scene, CheckOptions::default(), |_, _, _| {}).unwrap();
    assert!(matches!(failure(&v), Chi2Failure::Uncovered { .. }), "{}", v.report());
    // Its image is the built-in's: `mis+env` (the map by luminance) against `mis+env=env_cosine_mix`.
    let reference = render(&scene, Method::from_name("mis+env").unwrap(), 16384, 3);
    scene.techniques.push(mix);
    let r = pathlab::render::Renderer::new(gpu(), pipelines(), &scene, Method::from_name("mis+env=env_cosine_mix").unwrap(), 4).expect("renderer");
    let out = finish(r, 4096);
    assert_eq!(out.faults, 0);
    let z = z_test(&reference, &out.film, 0.01);
    println!("mis+env=env_cosine_mix (4096 spp) against mis+env (16384): {:.4} of {} channels pass, max |z| {:.2}, mean z {:+.3}", z.pass_fraction, z.channels, z.max_abs_z, z.mean_z);
    assert!(z.pass_fraction >= MIN_PASS, "{:.4} pass, max |z| {:.2}", z.pass_fraction, z.max_abs_z);
}

#[test]
fn a_technique_the_scene_cannot_test_is_not_proven_by_nothing() {
    // The study scene has no environment map: no configuration, no proof.
    let v = check(TechniqueKind::Env, &example("env_cosine_mix.wgsl")).unwrap();
    assert!(!v.passed() && v.results.is_empty());
    assert!(v.report().contains("verdict: REFUSED (env:env_cosine_mix: no configuration: an env technique samples an environment map, and the scene has none)"), "{}", v.report());
}

/// `advise` with a technique allowed unproven marks every row and the winner that use it, in the
/// table and in the JSON.
#[test]
fn advise_marks_the_rows_of_an_unproven_technique() {
    let study = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.toml");
    let technique = format!("bsdf:{}", example("phong_n_plus_2.wgsl").display());
    let args = ["advise", study.to_str().unwrap(), "--size", "64x32", "--target-rel-error", "1e-2", "--methods", "mis", "--pilot-seconds", "0.3", "--allow-unproven", "--technique", &technique];
    // In a folder of its own: the refused check writes its histogram into the current one.
    let dir = tempfile::tempdir().unwrap();
    let pathlab = || {
        let mut c = Command::new(env!("CARGO_BIN_EXE_pathlab"));
        c.current_dir(dir.path());
        c
    };
    let out = pathlab().args(args).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rows: Vec<&str> = stdout.lines().filter(|l| l.starts_with("mis")).collect();
    assert_eq!(rows.len(), 2, "{stdout}");
    for row in rows {
        assert_eq!(row.starts_with("mis+bsdf=phong_n_plus_2 (UNPROVEN) "), row.contains("phong_n_plus_2"), "{row}");
    }
    let out = pathlab().args(args).arg("--json").output().unwrap();
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["unproven"], serde_json::json!(["phong_n_plus_2"]));
    assert!(dir.path().join("phong_n_plus_2-check.png").exists(), "the refused check's histogram");
}

/// The Cornell box (two triangle lights) at 32x32.
fn cornell(techniques: &[PathBuf]) -> Scene {
    let mut scene = Scene::load(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/cornell_box.toml")).unwrap();
    scene.render.width = 32;
    scene.render.height = 32;
    scene.techniques = techniques.iter().map(|p| Technique::load(TechniqueKind::Light, p).unwrap()).collect();
    scene
}

/// A light technique for triangle lights: proven on the Cornell box's two light triangles (four
/// points of view each), the mistake of the missing cosine refused for its pdf's mass, a file
/// with both shapes' functions checked on both, one with neither named; the technique renders
/// the built-in image (`mis` against `mis+light=triangle_area`, per-pixel z-test), and the
/// mistake, rendered anyway, does not (the test's power).
#[test]
fn a_triangle_light_technique_is_proven_and_renders_the_built_in_image() {
    let scene = cornell(&[]);
    let check_on = |t: &Technique, scene: &Scene| technique::check(gpu(), t, scene, CheckOptions::default(), |_, _, _| {}).unwrap();
    let area = Technique::load(TechniqueKind::Light, example("triangle_area.wgsl")).unwrap();
    assert_eq!(area.light_shapes(), pathlab::scene::LightShapes { triangles: true, ..Default::default() });
    let v = check_on(&area, &scene);
    println!("{}", v.report());
    assert!(v.passed() && v.results.len() == 8, "{}", v.report());
    let mistake = Technique::load(TechniqueKind::Light, example("triangle_area_no_cosine.wgsl")).unwrap();
    let v = check_on(&mistake, &scene);
    match failure(&v) {
        // The mean cosine over the triangle seen from half its size on its normal.
        Chi2Failure::Mass { mass } => assert!(*mass < 0.9, "{mass}"),
        other => panic!("refused for another reason: {other}"),
    }

    // Both shapes in one file: spheres on the study scene's radii, the default triangle.
    let dir = tempfile::tempdir().unwrap();
    let both = dir.path().join("sphere_and_triangle_area.wgsl");
    let text = |f: &str| std::fs::read_to_string(example(f)).unwrap();
    std::fs::write(&both, text("sphere_area.wgsl") + &text("triangle_area.wgsl")).unwrap();
    let both = Technique::load(TechniqueKind::Light, &both).unwrap();
    assert_eq!(both.light_shapes(), pathlab::scene::LightShapes { spheres: true, triangles: true, ..Default::default() });
    let v = check_on(&both, &study_scene());
    assert!(v.passed() && v.results.len() == 12, "{}", v.report());
    assert!(v.source.contains("spherical light") && v.source.contains("right triangle"), "{}", v.source);
    // Neither shape: the contract is quoted.
    let neither = dir.path().join("neither.wgsl");
    std::fs::write(&neither, "fn my_helper(x: f32) -> f32 { return x; }\n").unwrap();
    let e = pathlab::shaders::validate_technique(&Technique::load(TechniqueKind::Light, &neither).unwrap()).unwrap_err().to_string();
    assert!(e.contains("no shape") && e.contains("fn sample_triangle_light_technique("), "{e}");

    // The image: the built-in `mis` (area sampling of the triangles) against the technique.
    // (Next event estimation alone, `nee`, is skewed here: from points beside the light its
    // 1 / dist^2 has a heavy tail, and the built-in `nee` itself gives a mean z of -0.24
    // against `mis` at 4096 spp, as does `nee+light=triangle_area`: so `mis` is the control,
    // `nee` shows the mistake's bias alone.)
    let reference = render(&scene, Preset::Mis.method(), 16384, 11);
    let scene = cornell(&[example("triangle_area.wgsl"), example("triangle_area_no_cosine.wgsl")]);
    let mut report = Vec::new();
    for (name, expect_pass) in [("mis+light=triangle_area", true), ("nee+light=triangle_area_no_cosine", false)] {
        let r = pathlab::render::Renderer::new(gpu(), pipelines(), &scene, Method::from_name(name).unwrap(), 12).expect("renderer");
        let out = finish(r, 4096);
        assert_eq!(out.faults, 0, "{name}: faults");
        let z = z_test(&reference, &out.film, 0.01);
        report.push(format!("{name} (4096 spp) against mis (16384): {:.4} of {} channels pass |z| <= {:.2}; max |z| {:.2}, mean z {:+.3}", z.pass_fraction, z.channels, z.threshold, z.max_abs_z, z.mean_z));
        assert_eq!(z.pass_fraction >= MIN_PASS, expect_pass, "{}", report.join("\n"));
    }
    println!("{}", report.join("\n"));
}

/// A microfacet technique of two alphas, on the anisotropic fixture (GGX and Beckmann brushed
/// metals, an anisotropic rough glass, an anisotropic principled sphere): the spherical caps
/// stretched by (alpha_u, alpha_v) are proven on its four classes of material, seen at 30
/// degrees of azimuth from u; the same with the axes swapped in the sampler alone is refused by
/// the chi-square test; a technique of one alpha is refused for the scene, naming the pair that
/// would serve, and a file that defines both pairs by validation. The caps render Mitsuba's
/// image of the fixture (per-pixel z-test on 2x2 blocks against its reference, as
/// tests/anisotropic.rs tests the built-ins), and a 5% bias would not pass.
#[test]
fn a_two_alpha_microfacet_technique_is_proven_on_anisotropic_materials_and_renders_mitsubas_image() {
    let reference = mitsuba_fixture("anisotropic");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let mut scene = Scene::load_with(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/anisotropic/anisotropic.xml"), &defines).unwrap();
    let check_on = |t: &Technique, scene: &Scene| technique::check(gpu(), t, scene, CheckOptions::default(), |_, _, _| {});
    let caps = Technique::load(TechniqueKind::Bsdf, example("ggx_spherical_caps.wgsl")).unwrap();
    let v = check_on(&caps, &scene).unwrap();
    println!("{}", v.report());
    assert!(v.passed() && v.results.len() == 12, "{}", v.report());
    for class in ["ggx alpha_u", "beckmann alpha_u", "(reflecting and refracting)"] {
        assert!(v.results.iter().any(|r| r.name.contains(class)), "no configuration of {class}:\n{}", v.report());
    }
    let swapped = Technique::load(TechniqueKind::Bsdf, broken("ggx_caps_swapped_axes.wgsl")).unwrap();
    let v = check_on(&swapped, &scene).unwrap();
    println!("{}", v.report());
    assert!(!v.passed() && v.worst().unwrap().failure.is_none() && v.worst().unwrap().p_value.unwrap() < v.level, "{}", v.report());
    let one_alpha = Technique::load(TechniqueKind::Bsdf, example("ggx_bounded_vndf.wgsl")).unwrap();
    let e = check_on(&one_alpha, &scene).unwrap_err().to_string();
    assert!(e.contains("anisotropic roughness") && e.contains("sample_microfacet_uv_technique"), "{e}");
    let dir = tempfile::tempdir().unwrap();
    let both = dir.path().join("both.wgsl");
    let text = |f: &str| std::fs::read_to_string(example(f)).unwrap();
    std::fs::write(&both, text("ggx_spherical_caps.wgsl") + &text("ggx_bounded_vndf.wgsl").replace("ggx_bounded_vndf_b", "bounded_b")).unwrap();
    let e = pathlab::shaders::validate_technique(&Technique::load(TechniqueKind::Bsdf, &both).unwrap()).unwrap_err().to_string();
    assert!(e.contains("defines both microfacet pairs"), "{e}");

    scene.techniques = vec![caps];
    let methods = [Method::from_name("mis+bsdf=ggx_spherical_caps").unwrap()];
    agrees_with_reference(&reference, &scene, &methods, |_| (2048, 2), 2900, methods[0]);
}

/// Light techniques for disk and cylinder lights, on the quadrics fixture (an elliptical disk
/// light, a small round one, and a glowing tube, a cylinder light): area sampling written as a
/// technique (`quadric_area.wgsl`, both shapes) and the visible arc of a cylinder
/// (`cylinder_visible_arc.wgsl`, a technique none of the built-ins is) are proven on every
/// configuration; sampling only the half of a cylinder that faces the point is refused, for
/// its pdf of 0 where the point sees the light from inside. Both proven techniques render
/// Mitsuba's image of the same file (per-pixel z-test on 2x2 blocks against its 65,536-spp
/// reference, as tests/quadrics.rs tests the built-ins), and a 5% bias would not pass.
#[test]
fn disk_and_cylinder_light_techniques_are_proven_and_render_mitsubas_image() {
    let reference = mitsuba_fixture("quadrics");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let load = |techniques: &[PathBuf]| {
        let mut scene = Scene::load_with(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/quadrics/quadrics.xml"), &defines).unwrap();
        scene.techniques = techniques.iter().map(|p| Technique::load(TechniqueKind::Light, p).unwrap()).collect();
        scene
    };
    let scene = load(&[]);
    let check_on = |t: &Technique| technique::check(gpu(), t, &scene, CheckOptions::default(), |_, _, _| {}).unwrap();
    let area = Technique::load(TechniqueKind::Light, example("quadric_area.wgsl")).unwrap();
    assert_eq!(area.light_shapes(), pathlab::scene::LightShapes { disks: true, cylinders: true, ..Default::default() });
    let v = check_on(&area);
    println!("{}", v.report());
    // Two distinct disks and one cylinder, four points of view each.
    assert!(v.passed() && v.results.len() == 12, "{}", v.report());
    let arc = Technique::load(TechniqueKind::Light, example("cylinder_visible_arc.wgsl")).unwrap();
    let v = check_on(&arc);
    println!("{}", v.report());
    assert!(v.passed() && v.results.len() == 4, "{}", v.report());
    let half = Technique::load(TechniqueKind::Light, broken("cylinder_facing_half.wgsl")).unwrap();
    let v = check_on(&half);
    println!("{}", v.report());
    assert!(matches!(failure(&v), Chi2Failure::Uncovered { .. }), "{}", v.report());
    assert!(v.results.iter().filter(|r| r.failure.is_some()).all(|r| r.name.contains("inside")), "refused only where it sees the inside:\n{}", v.report());

    // The README's study scene of the visible arc loads as it is.
    let tube = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/tube_lamp.xml")).unwrap();
    assert!(tube.warnings.is_empty() && tube.lights_of(pathlab::scene::EmitterKind::Cylinder).len() == 1, "{:?}", tube.warnings);

    let scene = load(&[example("quadric_area.wgsl"), example("cylinder_visible_arc.wgsl")]);
    let methods = ["mis+light=quadric_area", "mis+light=cylinder_visible_arc"].map(|m| Method::from_name(m).unwrap());
    agrees_with_reference(&reference, &scene, &methods, |_| (1024, 2), 2200, methods[0]);
}

/// A bsdf technique for microfacet normals: Dupuy and Benyoub's spherical caps (the visible
/// normals' density) proven on the conductors' and the rough glass's normals; Eto and
/// Tokuyoshi's bounded visible normals proven for reflection (on the conductors and on very
/// rough metals) and refused where a rough dielectric refracts about normals it never draws; a pdf without G1's normalisation refused
/// for its mass. Both render the built-in image of the two conductors (per-pixel z-test against
/// `mis`); the built-in images are unchanged (the seam costs nothing where no technique is
/// loaded: tests/render_presets.rs and the Mitsuba z-tests).
#[test]
fn a_microfacet_technique_is_proven_where_it_is_valid_and_renders_the_built_in_image() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let conductors = Scene::load(root.join("assets/scenes/cornell_conductors.xml")).unwrap();
    let glass = Scene::load(root.join("tests/fixtures/cornell_rough_glass/cornell_rough_glass.xml")).unwrap();
    let check_on = |t: &Technique, scene: &Scene| technique::check(gpu(), t, scene, CheckOptions::default(), |_, _, _| {}).unwrap();
    let caps = Technique::load(TechniqueKind::Bsdf, example("ggx_spherical_caps.wgsl")).unwrap();
    assert_eq!(caps.bsdf_targets(), pathlab::scene::BsdfTargets { phong: false, microfacet: false, microfacet_uv: true });
    for scene in [&conductors, &glass] {
        let v = check_on(&caps, scene);
        println!("{}", v.report());
        assert!(v.passed() && v.results.len() == 6, "{}", v.report());
    }
    let bounded = Technique::load(TechniqueKind::Bsdf, example("ggx_bounded_vndf.wgsl")).unwrap();
    let v = check_on(&bounded, &conductors);
    println!("{}", v.report());
    assert!(v.passed(), "{}", v.report());
    // At normal incidence every bounded sample reflects above the surface: its estimate of the
    // share of normals that do is exact, where the visible normals' has noise.
    let normal = v.results.iter().find(|r| r.name == "ggx alpha=0.2 (reflecting) at 0 degrees").unwrap();
    let (_, (_, technique_se), (_, builtin_se)) = normal.coverage.unwrap();
    assert!(technique_se < 0.01 * builtin_se, "{technique_se} against {builtin_se}");
    let v = check_on(&bounded, &glass);
    assert!(matches!(failure(&v), Chi2Failure::Uncovered { .. }), "{}", v.report());
    // Very rough metals (alpha 0.7 and 0.5): the bound cuts the cap where the normals' density
    // is large, a discontinuity the harness integrates on refined cells (without them the pdf's
    // mass came out 0.998487 and the check refused a correct technique).
    let grazing = Scene::load(root.join("assets/scenes/rough_metal_grazing.xml")).unwrap();
    let v = check_on(&bounded, &grazing);
    println!("{}", v.report());
    assert!(v.passed() && v.results.len() == 6, "{}", v.report());
    // The visible normals' density without G1: it integrates to 1 / G1(wo) > 1 off normal incidence.
    let dir = tempfile::tempdir().unwrap();
    let no_g1 = dir.path().join("vndf_no_g1.wgsl");
    let text = std::fs::read_to_string(example("ggx_spherical_caps.wgsl")).unwrap();
    std::fs::write(&no_g1, text.replace("let g1 = 2.0 * wo.z / (wo.z + t);", "let g1 = 1.0;")).unwrap();
    let v = check_on(&Technique::load(TechniqueKind::Bsdf, &no_g1).unwrap(), &conductors);
    match failure(&v) {
        Chi2Failure::Mass { mass } => assert!(*mass > 1.001, "{mass}"),
        other => panic!("refused for another reason: {other}"),
    }

    // The images: `mis` against each technique, per pixel.
    let mut scene = conductors;
    scene.render.width = 32;
    scene.render.height = 32;
    let reference = render(&scene, Preset::Mis.method(), 16384, 21);
    scene.techniques = vec![caps, bounded];
    let mut report = Vec::new();
    for name in ["mis+bsdf=ggx_spherical_caps", "mis+bsdf=ggx_bounded_vndf"] {
        let r = pathlab::render::Renderer::new(gpu(), pipelines(), &scene, Method::from_name(name).unwrap(), 22).expect("renderer");
        let out = finish(r, 4096);
        assert_eq!(out.faults, 0, "{name}: faults");
        let z = z_test(&reference, &out.film, 0.01);
        report.push(format!("{name} (4096 spp) against mis (16384): {:.4} of {} channels pass |z| <= {:.2}; max |z| {:.2}, mean z {:+.3}", z.pass_fraction, z.channels, z.threshold, z.max_abs_z, z.mean_z));
        assert!(z.pass_fraction >= MIN_PASS, "{}", report.join("\n"));
    }
    println!("{}", report.join("\n"));
}
