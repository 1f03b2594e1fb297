//! `pathlab compare` end to end: the metrics of two renders (JSON), the z-test when both carry
//! variances, the error map, and clear refusals of mismatched or unreadable inputs.

use std::path::{Path, PathBuf};
use std::process::Command;

fn pathlab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pathlab"))
}

fn study() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.toml")
}

fn render(dir: &Path, name: &str, args: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let status = pathlab()
        .arg("render")
        .arg(study())
        .args(args)
        .args(["--quiet", "--variance", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
    out
}

#[test]
fn compare_two_renders() {
    let dir = tempfile::tempdir().unwrap();
    let size = ["--width", "48", "--height", "24"];
    let reference = render(dir.path(), "ref.exr", &[&size[..], &["--method", "best", "--spp", "16384"]].concat());
    let test = render(dir.path(), "test.exr", &[&size[..], &["--method", "mis", "--spp", "4096", "--seed", "3"]].concat());
    let map = dir.path().join("error.png");
    let out = pathlab().arg("compare").arg(&test).arg(&reference).args(["--json", "--display", "gamma:1.6", "--error-map"]).arg(&map).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in ["mse", "rel_mse", "psnr", "ssim", "flip"] {
        let x = v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"));
        assert!(x.is_finite() && x > 0.0, "{key} = {x}");
    }
    assert!(v["ssim"].as_f64().unwrap() < 1.0 && v["flip"].as_f64().unwrap() < 1.0);
    assert_eq!(v["display"], "gamma:1.6");
    assert_eq!(v["bias"].as_array().unwrap().len(), 3);
    assert!(v["bias"][0]["std_error"].as_f64().unwrap() > 0.0);
    // Both carry variances: the z-test ran, and mis agrees with best in expectation (at 4096
    // spp per pixel the normal approximation holds; at 16 spp it does not).
    assert_eq!(v["z_test"]["passed"], true, "{v}");
    let png = image::open(&map).unwrap();
    assert!(png.width() > 48 && png.height() >= 24, "the map has a colour bar beside the image");

    // The same image against itself: zero error, perfect scores.
    let same = pathlab().arg("compare").arg(&test).arg(&test).arg("--json").output().unwrap();
    let s: serde_json::Value = serde_json::from_slice(&same.stdout).unwrap();
    assert_eq!(s["mse"].as_f64(), Some(0.0));
    assert_eq!(s["ssim"].as_f64(), Some(1.0));

    // The z-test on 4x4 blocks.
    let blocks = pathlab().arg("compare").arg(&test).arg(&reference).args(["--json", "--block", "4"]).output().unwrap();
    let b: serde_json::Value = serde_json::from_slice(&blocks.stdout).unwrap();
    assert_eq!(b["z_test"]["block"], 4);
    assert_eq!(b["z_test"]["channels"], 12 * 6 * 3);
    let bad_block = pathlab().arg("compare").arg(&test).arg(&reference).args(["--block", "5"]).output().unwrap();
    assert_eq!(bad_block.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&bad_block.stderr).contains("must divide"));

    // The human-readable table names every metric.
    let table = pathlab().arg("compare").arg(&test).arg(&reference).output().unwrap();
    let text = String::from_utf8_lossy(&table.stdout);
    for word in ["MSE", "relMSE", "bias R", "PSNR", "SSIM", "FLIP", "z-test"] {
        assert!(text.contains(word), "{word} missing:\n{text}");
    }
}

#[test]
fn compare_refuses_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let a = render(dir.path(), "a.exr", &["--width", "16", "--height", "8", "--spp", "2"]);
    let b = render(dir.path(), "b.exr", &["--width", "16", "--height", "16", "--spp", "2"]);
    let not_exr = dir.path().join("scene.exr");
    std::fs::write(&not_exr, "[camera]\n").unwrap();
    let run = |x: &Path, y: &Path| {
        let out = pathlab().arg("compare").arg(x).arg(y).output().unwrap();
        (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
    };
    let (code, err) = run(&a, &b);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("differ in size") && err.contains("16x8") && err.contains("16x16"), "{err}");
    let (code, err) = run(&a, &not_exr);
    assert_eq!(code, Some(1));
    assert!(err.contains("scene.exr") && err.contains("not a readable OpenEXR file"), "{err}");
    let (code, err) = run(&dir.path().join("missing.exr"), &a);
    assert_eq!(code, Some(1));
    assert!(err.contains("missing.exr") && err.contains("no such file"), "{err}");
    assert!(!err.contains("panicked"));
}
