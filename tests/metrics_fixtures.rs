//! PSNR, SSIM and FLIP against the libraries people trust: `scripts/metrics_fixtures.py`
//! computed them with scikit-image (`peak_signal_noise_ratio`, `structural_similarity` with
//! `channel_axis=2, data_range=1.0`) and NVIDIA's `flip-evaluator` (LDR, 67 ppd) on the committed
//! image pairs of `tests/fixtures/metrics/`. pathlab must match PSNR and SSIM to 1e-4 and FLIP to
//! 1e-3. Deterministic: no tolerance for chance.

use std::path::Path;

use pathlab::display::DisplayImage;
use pathlab::metrics::{flip, psnr, ssim};

fn fixtures() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/metrics")
}

fn load(name: &str, width: u32, height: u32) -> DisplayImage {
    let bytes = std::fs::read(fixtures().join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
    let values: Vec<f32> = bytes.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
    assert_eq!(values.len(), (width * height * 3) as usize, "{name}: size");
    DisplayImage { width, height, pixels: values.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect() }
}

#[test]
fn psnr_ssim_flip_match_scikit_image_and_flip_evaluator() {
    let text = std::fs::read_to_string(fixtures().join("expected.json")).unwrap();
    let expected: serde_json::Value = serde_json::from_str(&text).unwrap();
    let pairs = expected["pairs"].as_array().unwrap();
    assert!(pairs.len() >= 4);
    let mut failures = Vec::new();
    for p in pairs {
        let name = p["name"].as_str().unwrap();
        let (w, h) = (p["width"].as_u64().unwrap() as u32, p["height"].as_u64().unwrap() as u32);
        let reference = load(&format!("{name}_ref.f32"), w, h);
        let test = load(&format!("{name}_test.f32"), w, h);
        let ours = [psnr(&reference, &test), ssim(&reference, &test), flip(&reference, &test)];
        let theirs = [p["psnr"].as_f64().unwrap(), p["ssim"].as_f64().unwrap(), p["flip"].as_f64().unwrap()];
        for ((metric, tol), (a, b)) in [("PSNR", 1e-4), ("SSIM", 1e-4), ("FLIP", 1e-3)].iter().zip(ours.iter().zip(theirs)) {
            println!("{name} {metric}: pathlab {a:.6}, reference {b:.6}, difference {:.2e}", (a - b).abs());
            if (a - b).abs() > *tol {
                failures.push(format!("{name} {metric}: {a} vs {b}"));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn identical_images_score_perfectly() {
    let img = load("gradient_noise_ref.f32", 64, 48);
    assert_eq!(psnr(&img, &img), f64::INFINITY);
    assert!((ssim(&img, &img) - 1.0).abs() < 1e-12);
    assert_eq!(flip(&img, &img), 0.0);
}
