//! `pathlab study` end to end on lavapipe: the quick study with every preset and both biased
//! demonstrations (every output exists and parses, the tables hold every method, the bias
//! verdicts pass every unbiased preset and flag both biased ones), an interrupted study that
//! resumes its reference to the same image bit for bit, and bad input refused before any GPU
//! work.
//!
//! Verdict error rates: a study's verdicts wrongly flag some unbiased method with probability
//! below 0.01 (`study::verdict`); the study's seeds are fixed, so this test is deterministic
//! on a given driver.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use pathlab::output::read_exr;

fn pathlab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pathlab"))
}

fn study() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.toml")
}

const ALL: &str = "plain,halton,cosine,phong,nee,mis,best,phong-lobe-only,nee-double-count";

#[test]
fn quick_study_writes_every_output_and_judges_bias() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    // Two regions, written for twice the quick size: scaled to 128x64.
    let regions = dir.path().join("regions.toml");
    std::fs::write(&regions, "size = [256, 128]\n[[region]]\nname = \"left\"\nx = 0\ny = 0\nwidth = 128\nheight = 128\n[[region]]\nname = \"a corner\"\nx = 240\ny = 112\nwidth = 16\nheight = 16\n").unwrap();
    let run = pathlab().arg("study").arg(study()).arg("--out").arg(&out).args(["--quick", "--quiet", "--methods", ALL, "--regions"]).arg(&regions).output().unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(stderr.contains("wrote") && stderr.contains("report.md"), "{stderr}");
    for file in pathlab::study::layout(&out) {
        assert!(file.is_file(), "{} missing", file.display());
    }
    for png in ["grid.png", "relmse_vs_spp.png", "relmse_vs_seconds.png"] {
        let img = image::open(out.join(png)).unwrap_or_else(|e| panic!("{png}: {e}"));
        assert!(img.width() > 300 && img.height() > 200, "{png}");
    }
    let results: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    let methods: Vec<&str> = ALL.split(',').collect();
    for table in ["equal_samples", "equal_time"] {
        let rows = results[table].as_array().unwrap();
        for m in &methods {
            assert!(rows.iter().any(|r| r["method"] == *m), "{table} lacks {m}");
        }
        for r in rows {
            for key in ["psnr", "ssim", "flip", "mse", "rel_mse", "seconds", "pixel_samples_per_second"] {
                assert!(r[key]["mean"].as_f64().is_some_and(f64::is_finite), "{table} {key}: {r}");
            }
        }
    }
    // 5 spp budgets x 2 seeds + 2 time budgets x 2 seeds per method.
    assert_eq!(results["runs"].as_array().unwrap().len(), methods.len() * 14);
    // Every run measured both regions; each table row has their statistics.
    for run in results["runs"].as_array().unwrap() {
        let r = run["regions"].as_array().unwrap();
        assert!(r.len() == 2 && r[0]["name"] == "left" && r[1]["rel_mse"].as_f64().is_some_and(|v| v.is_finite() && v >= 0.0), "{run}");
    }
    assert!(results["equal_time"].as_array().unwrap().iter().all(|r| r["regions"][1]["rel_mse"]["mean"].as_f64().is_some()));
    for v in results["verdicts"].as_array().unwrap() {
        let (name, detected, demo) = (v["method"].as_str().unwrap(), v["bias_detected"].as_bool().unwrap(), v["biased_demonstration"].as_bool().unwrap());
        assert_eq!(detected, demo, "{name}: {}", v["text"]);
    }
    assert!(results["equal_time"].as_array().unwrap().iter().any(|r| r["method"] == "best" && r["efficiency_vs_plain"].as_f64().unwrap() > 1.0));
    let csv = std::fs::read_to_string(out.join("convergence.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + methods.len() * 14);
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    for heading in ["## Reference", "## Equal samples", "## Equal time", "## Convergence", "## Bias verdicts", "grid.png"] {
        assert!(report.contains(heading), "{heading} missing from report.md");
    }
    assert!(report.contains("biased, as expected of this demonstration"));
    assert!(report.contains("## Regions (equal time, 0.3 s)") && report.contains("| a corner |"), "no region table in report.md");

    // A rerun reuses every run and the cached reference.
    let again = pathlab().arg("study").arg(study()).arg("--out").arg(&out).args(["--quick", "--quiet", "--methods", ALL, "--regions"]).arg(&regions).output().unwrap();
    let stderr = String::from_utf8_lossy(&again.stderr);
    assert!(again.status.success(), "{stderr}");
    assert!(stderr.contains("reference: reusing") && stderr.contains(&format!("{} runs reused", methods.len() * 14)), "{stderr}");
}

/// SIGKILL during the reference render, then the same command again: the reference continues
/// from its checkpoint and equals an uninterrupted render of the same method, seed and spp.
#[cfg(unix)]
#[test]
fn killed_study_resumes_its_reference_bit_for_bit() {
    let reference_spp = (40000 * crate::common::work_scale()).to_string();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let args = |c: &mut Command| {
        c.arg("study").arg(study()).arg("--out").arg(&out).args([
            "--size", "32x16", "--methods", "plain", "--spp", "1", "--time", "0.05", "--seeds", "1", "--reference-spp", reference_spp.as_str(),
            "--checkpoint-every", "0.3", "--quiet",
        ]);
    };
    let mut cmd = pathlab();
    args(&mut cmd);
    let mut child = cmd.stderr(Stdio::null()).spawn().unwrap();
    let checkpoint = out.join("reference.checkpoint.exr");
    let start = Instant::now();
    while !checkpoint.exists() {
        assert!(start.elapsed() < Duration::from_secs(120), "no checkpoint appeared");
        std::thread::sleep(Duration::from_millis(50));
    }
    std::thread::sleep(Duration::from_millis(400));
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!out.join("report.md").exists(), "killed before the end");
    let saved = pathlab::render::Checkpoint::read(&checkpoint).expect("the checkpoint on disk is always readable");
    assert!(saved.spp > 0 && saved.spp < 40000 * crate::common::work_scale(), "interrupted mid-way: {} spp", saved.spp);

    let mut cmd = pathlab();
    args(&mut cmd);
    let resumed = cmd.output().unwrap();
    let stderr = String::from_utf8_lossy(&resumed.stderr);
    assert!(resumed.status.success(), "{stderr}");
    assert!(stderr.contains("continuing from"), "{stderr}");

    let single = dir.path().join("single.exr");
    let r = pathlab()
        .arg("render")
        .arg(study())
        .args(["--width", "32", "--height", "16", "--method", "best", "--seed", "1000003", "--spp", reference_spp.as_str(), "--variance", "--quiet", "-o"])
        .arg(&single)
        .output()
        .unwrap();
    assert!(r.status.success());
    let (a, _) = read_exr(&out.join("reference.exr")).unwrap();
    let (b, _) = read_exr(&single).unwrap();
    let bits = |f: &pathlab::film::Film| f.mean.iter().chain(&f.variance).flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(a.spp, 40000 * crate::common::work_scale());
    assert!(bits(&a) == bits(&b), "resumed reference differs from an uninterrupted render");
}

#[test]
fn bad_input_is_refused_before_any_gpu_work() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s");
    let run = |extra: &[&str], out: &Path| {
        let o = pathlab()
            .env("VK_ICD_FILENAMES", dir.path().join("none.json"))
            .env("VK_DRIVER_FILES", dir.path().join("none.json"))
            .arg("study")
            .arg(study())
            .arg("--out")
            .arg(out)
            .args(extra)
            .output()
            .unwrap();
        (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let (code, err) = run(&["--methods", "plain,fancy"], &out);
    assert_eq!(code, Some(1));
    assert!(err.contains("unknown method `fancy`") && err.contains("nee-double-count"), "{err}");
    let (code, err) = run(&["--reference", "nowhere.exr"], &out);
    assert_eq!(code, Some(1));
    assert!(err.contains("nowhere.exr") && err.contains("no such file"), "{err}");
    let (code, err) = run(&["--spp", "1,0"], &out);
    assert_eq!(code, Some(1));
    assert!(err.contains("--spp"), "{err}");
    let (code, err) = run(&["--time", "abc"], &out);
    assert_eq!(code, Some(1));
    assert!(err.contains("--time") && err.contains("abc"), "{err}");
    // A reference of another size than --size.
    let small = dir.path().join("small.exr");
    let film = pathlab::film::Film { width: 8, height: 8, spp: 1, mean: vec![[0.5; 3]; 64], variance: vec![[0.0; 3]; 64] };
    pathlab::output::write_exr(&small, &film, &Vec::new(), false).unwrap();
    let (code, err) = run(&["--reference", small.to_str().unwrap(), "--size", "16x8"], &out);
    assert_eq!(code, Some(1));
    assert!(err.contains("8x8") && err.contains("16x8"), "{err}");
    // A directory that cannot be created (its parent is a file).
    let file = dir.path().join("plainfile");
    std::fs::write(&file, "x").unwrap();
    let (code, err) = run(&["--quick"], &file.join("sub"));
    assert_eq!(code, Some(1));
    assert!(err.contains("cannot use the study directory") && err.contains("plainfile"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}
