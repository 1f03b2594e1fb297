//! Split renders: shards of every sampler, merged, equal the single run of the same total
//! range (up to the rounding of the summation order: each f32 Kahan-compensated part is summed
//! in f64, where the single run compensates in f32 throughout; tolerance 2e-6 relative per
//! pixel value); bad sets of parts are refused naming the file, without touching an existing
//! output; a render killed with SIGKILL resumes from its checkpoint to the uninterrupted image.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use pathlab::method::Sampler;
use pathlab::output::read_exr;

fn pathlab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pathlab"))
}

fn study() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.toml")
}

const SIZE: [&str; 4] = ["--width", "32", "--height", "16"];
/// Relative tolerance of merged against single-run pixel values.
const TOLERANCE: f64 = 2e-6;

fn ok(out: Output) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{stderr}");
    stderr
}

fn render(extra: &[&str], out: &Path) -> Output {
    pathlab().arg("render").arg(study()).args(SIZE).args(extra).arg("--quiet").arg("-o").arg(out).output().unwrap()
}

fn merge(parts: &[PathBuf], out: &Path, extra: &[&str]) -> Output {
    pathlab().arg("merge").args(parts).arg("-o").arg(out).args(extra).output().unwrap()
}

/// Largest |a - b| / max(|b|, 1e-3) over every mean value, and the same for variances.
fn max_rel_diff(a: &pathlab::film::Film, b: &pathlab::film::Film) -> (f64, f64) {
    let rel = |x: &[[f32; 3]], y: &[[f32; 3]]| {
        x.iter().flatten().zip(y.iter().flatten()).map(|(&p, &q)| (p as f64 - q as f64).abs() / (q as f64).abs().max(1e-3)).fold(0.0, f64::max)
    };
    (rel(&a.mean, &b.mean), rel(&a.variance, &b.variance))
}

#[test]
fn merged_shards_equal_the_single_run_for_every_sampler() {
    let dir = tempfile::tempdir().unwrap();
    for sampler in Sampler::ALL {
        let s = sampler.name();
        let method = ["--method", "mis", "--sampler", s, "--seed", "5"];
        let single = dir.path().join(format!("{s}-single.exr"));
        ok(render(&[&method[..], &["--spp", "96", "--variance"]].concat(), &single));
        let parts: Vec<PathBuf> = (0..3).map(|i| dir.path().join(format!("{s}-part{i}.exr"))).collect();
        for (i, part) in parts.iter().enumerate() {
            ok(render(&[&method[..], &["--spp", "96", "--shard", &format!("{i}/3")]].concat(), part));
        }
        // Uneven explicit ranges too, given in any order.
        let ranges = ["50..96", "0..7", "7..50"];
        let explicit: Vec<PathBuf> = ranges.iter().enumerate().map(|(i, _)| dir.path().join(format!("{s}-range{i}.exr"))).collect();
        for (r, p) in ranges.iter().zip(&explicit) {
            ok(render(&[&method[..], &["--samples", r]].concat(), p));
        }
        let (reference, _) = read_exr(&single).unwrap();
        for (name, set) in [("shards", &parts), ("ranges", &explicit)] {
            let merged = dir.path().join(format!("{s}-{name}-merged.exr"));
            ok(merge(set, &merged, &["--variance"]));
            let (film, metadata) = read_exr(&merged).unwrap();
            assert_eq!(film.spp, 96);
            assert!(metadata.iter().any(|(k, v)| k == "sampler" && v == s));
            let (dm, dv) = max_rel_diff(&film, &reference);
            println!("{s} {name}: max relative difference to the single run: mean {dm:.2e}, variance {dv:.2e}");
            assert!(dm <= TOLERANCE && dv <= 1e-4, "{s} {name}: merged differs from the single run: mean {dm:.2e}, variance {dv:.2e}");
        }
    }
}

#[test]
fn bad_parts_are_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let part = |name: &str, extra: &[&str]| {
        let p = d.join(name);
        ok(render(&[&["--method", "nee", "--seed", "1"][..], extra].concat(), &p));
        p
    };
    let a = part("a.exr", &["--samples", "0..8"]);
    let b = part("b.exr", &["--samples", "8..16"]);
    let overlap = part("overlap.exr", &["--samples", "4..12"]);
    let seed = pathlab().arg("render").arg(study()).args(SIZE).args(["--method", "nee", "--seed", "2", "--samples", "8..16", "--quiet", "-o"]).arg(d.join("seed.exr")).output().unwrap();
    ok(seed);
    let method = pathlab().arg("render").arg(study()).args(SIZE).args(["--method", "mis", "--seed", "1", "--samples", "8..16", "--quiet", "-o"]).arg(d.join("method.exr")).output().unwrap();
    ok(method);
    let size = pathlab().arg("render").arg(study()).args(["--width", "16", "--height", "16", "--method", "nee", "--seed", "1", "--samples", "8..16", "--quiet", "-o"]).arg(d.join("size.exr")).output().unwrap();
    ok(size);
    let shard0 = part("s0.exr", &["--spp", "12", "--shard", "0/3"]);
    let shard2 = part("s2.exr", &["--spp", "12", "--shard", "2/3"]);
    let truncated = d.join("truncated.exr");
    let bytes = std::fs::read(&b).unwrap();
    std::fs::write(&truncated, &bytes[..bytes.len() * 2 / 3]).unwrap();
    let not_exr = d.join("notes.exr");
    std::fs::write(&not_exr, "hello").unwrap();

    let out = d.join("out.exr");
    std::fs::write(&out, b"keep me").unwrap();
    let cases: Vec<(&str, Vec<PathBuf>, Vec<&str>)> = vec![
        ("overlap", vec![a.clone(), overlap.clone()], vec!["overlap.exr", "overlaps", "a.exr"]),
        ("seed", vec![a.clone(), d.join("seed.exr")], vec!["seed.exr", "seed is 2", "a.exr"]),
        ("method", vec![a.clone(), d.join("method.exr")], vec!["method.exr", "bsdf"]),
        ("size", vec![a.clone(), d.join("size.exr")], vec!["size.exr", "width is 16"]),
        ("missing shard", vec![shard0.clone(), shard2.clone()], vec!["4..8", "--allow-gaps"]),
        ("missing first range", vec![b.clone()], vec!["0..8"]),
        ("truncated", vec![a.clone(), truncated.clone()], vec!["truncated.exr", "cannot read it"]),
        ("not an EXR", vec![not_exr.clone()], vec!["notes.exr"]),
    ];
    for (name, parts, words) in cases {
        let o = merge(&parts, &out, &[]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{name}: {stderr}");
        for w in words {
            assert!(stderr.contains(w), "{name}: `{w}` missing from: {stderr}");
        }
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
        assert_eq!(std::fs::read(&out).unwrap(), b"keep me", "{name}: the existing output was touched");
    }
    // With --allow-gaps the missing shard is merged around and recorded.
    let o = merge(&[shard0, shard2], &out, &["--allow-gaps"]);
    ok(o);
    let (film, metadata) = read_exr(&out).unwrap();
    assert_eq!(film.spp, 8);
    assert!(metadata.iter().any(|(k, v)| k == "missing_samples" && v == "4..8"), "{metadata:?}");
    // A whole render is not a part.
    let whole = d.join("whole.exr");
    ok(render(&["--spp", "2"], &whole));
    let o = merge(&[whole], &d.join("x.exr"), &[]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("not a pathlab accumulator file"));
}

/// `render --checkpoint F`, SIGKILL mid-way, `render --resume F`: the same image as a render
/// that never stopped, and the checkpoint on disk readable at every moment we look.
#[cfg(unix)]
#[test]
fn killed_render_resumes_to_the_uninterrupted_image() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let checkpoint = d.join("ck.exr");
    let spp = (60000 * crate::common::work_scale()).to_string();
    let args = ["--method", "best", "--spp", spp.as_str(), "--seed", "3", "--checkpoint-every", "0.2"];
    let mut child = pathlab()
        .arg("render")
        .arg(study())
        .args(SIZE)
        .args(args)
        .arg("--checkpoint")
        .arg(&checkpoint)
        .args(["--quiet", "-o"])
        .arg(d.join("killed.exr"))
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let mut reads = 0;
    while reads < 5 {
        assert!(start.elapsed() < Duration::from_secs(120), "no checkpoints appeared");
        if checkpoint.exists() {
            let c = pathlab::render::Checkpoint::read(&checkpoint).expect("a checkpoint on disk is always complete");
            assert!(c.spp > 0);
            reads += 1;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!d.join("killed.exr").exists(), "killed before the end");
    let saved = pathlab::render::Checkpoint::read(&checkpoint).unwrap();
    assert!(saved.spp < 60000 * crate::common::work_scale(), "killed mid-way ({} spp saved)", saved.spp);

    let resumed = d.join("resumed.exr");
    let o = pathlab().arg("render").arg(study()).args(SIZE).args(args).arg("--resume").arg(&checkpoint).args(["--quiet", "-o"]).arg(&resumed).output().unwrap();
    ok(o);
    let single = d.join("single.exr");
    ok(render(&["--method", "best", "--spp", spp.as_str(), "--seed", "3"], &single));
    let bits = |p: &Path| read_exr(p).unwrap().0.mean.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert!(bits(&resumed) == bits(&single), "resumed render differs from the uninterrupted one");
    // Resuming from a checkpoint of another seed is refused, naming the field.
    let o = pathlab().arg("render").arg(study()).args(SIZE).args(["--method", "best", "--spp", spp.as_str(), "--seed", "4", "--resume"]).arg(&checkpoint).args(["--quiet", "-o"]).arg(d.join("other.exr")).output().unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("seed"));
}
