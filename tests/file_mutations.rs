//! The EXR files pathlab reads back (split-render parts, checkpoints, references), corrupted in
//! several hundred seeded ways (`pathlab::output::mutation`) and given to `merge`,
//! `render --resume`, `compare` and the study's reference loader, as a user would. Every case
//! must end in a clean refusal (non-zero exit, the file named, an existing output untouched, no
//! panic, signal or hang) or, for damage that cannot matter, in exactly the unmutated result.
//! A panic, a signal, a timeout, an unnamed refusal or an accepted wrong result fails the test.
//! Deterministic: fixed seeds; no statistics involved.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use pathlab::output::mutation::{mutants, Expect, Mutant, Plan};
use pathlab::output::read_exr;

fn pathlab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pathlab"))
}

fn study() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.toml")
}

const SIZE: [&str; 4] = ["--width", "16", "--height", "8"];
const PLAN: Plan = Plan { flips: 20, values_per_attribute: 5, channels: 3 };
const TIMEOUT: Duration = Duration::from_secs(60);
const SENTINEL: &[u8] = b"an existing output that a refused command must leave alone";

struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

/// Runs `cmd`, killing it after `TIMEOUT`.
fn run(mut cmd: Command) -> Run {
    let mut child = cmd.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("start pathlab");
    let start = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let out = child.wait_with_output().unwrap();
            return Run { code: Some(-999), stdout: String::new(), stderr: format!("TIMEOUT\n{}", String::from_utf8_lossy(&out.stderr)) };
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    let out = child.wait_with_output().unwrap();
    Run { code: out.status.code(), stdout: String::from_utf8_lossy(&out.stdout).into_owned(), stderr: String::from_utf8_lossy(&out.stderr).into_owned() }
}

fn ok(r: Run) -> Run {
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    r
}

/// Outcome counts per command, and the failures.
#[derive(Default)]
struct Tally {
    counts: BTreeMap<(String, &'static str), usize>,
    failures: Vec<String>,
}

impl Tally {
    /// Classifies one run on `mutant` (written at `file`): a clean refusal, or `same` (the
    /// result equals the unmutated one) where the mutant allows it.
    fn judge(&mut self, command: &str, mutant: &Mutant, file: &Path, r: &Run, output: Option<&Path>, same: impl FnOnce() -> bool) {
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        let untouched = output.is_none_or(|o| std::fs::read(o).is_ok_and(|b| b == SENTINEL));
        let outcome = match r.code {
            None => Err("killed by a signal".to_string()),
            Some(-999) => Err("timed out".to_string()),
            _ if r.stderr.contains("panicked") => Err("panicked".to_string()),
            Some(0) if mutant.expect == Expect::RefuseOrSame && same() => Ok("same result"),
            Some(0) => Err("accepted, with a result other than the unmutated file's".to_string()),
            Some(_) if !r.stderr.contains(&name) => Err(format!("refused without naming the file: {}", r.stderr.trim())),
            Some(_) if !untouched => Err("refused, but the existing output was changed".to_string()),
            Some(_) => Ok("refused, naming the file"),
        };
        match outcome {
            Ok(o) => *self.counts.entry((command.to_string(), o)).or_default() += 1,
            Err(why) => {
                *self.counts.entry((command.to_string(), "FAILED")).or_default() += 1;
                self.failures.push(format!("{command}: {}: {why}", mutant.label));
            }
        }
    }
}

/// What an image file holds: spp, every value's bits, and its pathlab attributes but those
/// that differ between runs of one command (the attribute order of the file, its checksum and
/// the time the command took are not its content).
fn content(path: &Path) -> Option<(u64, Vec<u32>, Vec<(String, String)>)> {
    let (film, mut metadata) = read_exr(path).ok()?;
    metadata.retain(|(k, _)| !["render_seconds", "data_sha256"].contains(&k.as_str()));
    Some((film.spp, film.mean.iter().chain(&film.variance).flatten().map(|x| x.to_bits()).collect(), metadata))
}

fn pixels(film: &pathlab::film::Film) -> Vec<u32> {
    film.mean.iter().chain(&film.variance).flatten().map(|x| x.to_bits()).collect()
}

/// Renders `extra` of the study scene at 16x8 to `out`.
fn render_to(extra: &[&str], out: &Path) {
    let mut c = pathlab();
    c.arg("render").arg(study()).args(SIZE).args(extra).arg("--quiet").arg("-o").arg(out);
    ok(run(c));
}

/// The files the mutations start from, in `d`: two shards of 8 spp, a reference (16 spp) and a
/// test image (4 spp), both with variance.
struct Originals {
    p0: PathBuf,
    p1: PathBuf,
    reference: PathBuf,
    test: PathBuf,
}

fn originals(d: &Path) -> Originals {
    let o = Originals { p0: d.join("p0.exr"), p1: d.join("p1.exr"), reference: d.join("ref.exr"), test: d.join("test.exr") };
    render_to(&["--spp", "8", "--shard", "0/2"], &o.p0);
    render_to(&["--spp", "8", "--shard", "1/2"], &o.p1);
    render_to(&["--spp", "16", "--variance", "--seed", "1"], &o.reference);
    render_to(&["--spp", "4", "--variance", "--seed", "2"], &o.test);
    o
}

#[test]
fn corrupted_parts_checkpoints_and_references_are_refused_by_name_or_change_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The originals: two shards, a finished checkpoint, a reference and a test image.
    let Originals { p0, p1, reference, test } = originals(d);
    let checkpoint = d.join("c.exr");
    render_to(&["--spp", "8", "--checkpoint", checkpoint.to_str().unwrap()], &d.join("c-image.exr"));

    let merge = |part: &Path, out: &Path| {
        let mut c = pathlab();
        c.arg("merge").arg(&p0).arg(part).arg("-o").arg(out);
        run(c)
    };
    let resume = |file: &Path, out: &Path| {
        let mut c = pathlab();
        c.arg("render").arg(study()).args(SIZE).args(["--spp", "8", "--quiet", "--resume"]).arg(file).arg("-o").arg(out);
        run(c)
    };
    let compare = |t: &Path, r: &Path| {
        let mut c = pathlab();
        c.arg("compare").arg(t).arg(r).arg("--json");
        run(c)
    };
    // The unmutated results.
    let merged = d.join("merged.exr");
    ok(merge(&p1, &merged));
    let merged_content = content(&merged).unwrap();
    let merged_seconds = read_exr(&merged).unwrap().1.into_iter().find(|(k, _)| k == "render_seconds");
    let resumed = d.join("resumed.exr");
    let copy = d.join("c-copy.exr");
    std::fs::copy(&checkpoint, &copy).unwrap();
    ok(resume(&copy, &resumed));
    let resumed_content = content(&resumed).unwrap();
    let compared = ok(compare(&test, &reference)).stdout;
    let mut scene = pathlab::scene::Scene::load(study()).unwrap();
    (scene.render.width, scene.render.height) = (16, 8);
    let loaded = pathlab::study::reference::load_file(&reference, &scene).expect("the unmutated reference loads");

    let mut tally = Tally::default();
    let case = |k: usize, m: &Mutant| {
        let file = d.join(format!("m{k:04}.exr"));
        std::fs::write(&file, &m.bytes).unwrap();
        file
    };
    let start = Instant::now();
    // merge: the second shard corrupted.
    for (k, m) in mutants(&p1, 17, PLAN).unwrap().iter().enumerate() {
        let file = case(k, m);
        let out = d.join("out.exr");
        std::fs::write(&out, SENTINEL).unwrap();
        let r = merge(&file, &out);
        let same = || {
            content(&out).as_ref() == Some(&merged_content)
                && read_exr(&out).unwrap().1.into_iter().find(|(k, _)| k == "render_seconds") == merged_seconds
        };
        tally.judge("merge", m, &file, &r, Some(&out), same);
    }
    // render --resume: the checkpoint corrupted.
    for (k, m) in mutants(&checkpoint, 29, PLAN).unwrap().iter().enumerate() {
        let file = case(k, m);
        let out = d.join("out.exr");
        std::fs::write(&out, SENTINEL).unwrap();
        let r = resume(&file, &out);
        tally.judge("render --resume", m, &file, &r, Some(&out), || content(&out).as_ref() == Some(&resumed_content));
    }
    // compare: the reference corrupted, then the test image.
    for (k, m) in mutants(&reference, 41, PLAN).unwrap().iter().enumerate() {
        let file = case(k, m);
        let r = compare(&test, &file);
        tally.judge("compare (reference)", m, &file, &r, None, || r.stdout == compared);
        // The study's reference loader, in the library: refused naming the file, or the same film.
        let loader = match pathlab::study::reference::load_file(&file, &scene) {
            Ok(x) => Run { code: Some(0), stdout: String::new(), stderr: if pixels(&x.film) == pixels(&loaded.film) { String::new() } else { "different".into() } },
            Err(e) => Run { code: Some(1), stdout: String::new(), stderr: e.to_string() },
        };
        tally.judge("study reference", m, &file, &loader, None, || loader.stderr.is_empty());
    }
    for (k, m) in mutants(&test, 53, PLAN).unwrap().iter().enumerate() {
        let file = case(k, m);
        let r = compare(&file, &reference);
        tally.judge("compare (test image)", m, &file, &r, None, || r.stdout == compared);
    }
    let seconds = start.elapsed().as_secs_f64();
    println!("{:<22} {:<26} {:>6}", "command", "outcome", "cases");
    for ((command, outcome), n) in &tally.counts {
        println!("{command:<22} {outcome:<26} {n:>6}");
    }
    println!("{} cases in {seconds:.1} s", tally.counts.values().sum::<usize>());
    assert!(tally.failures.is_empty(), "{} of the mutated files were mishandled:\n{}", tally.failures.len(), tally.failures.join("\n"));
}

#[test]
fn a_study_refuses_a_bad_reference_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let render = |extra: &[&str], out: &Path| {
        let mut c = pathlab();
        c.arg("render").arg(study()).args(SIZE).args(extra).args(["--spp", "4", "--variance", "--quiet"]).arg("-o").arg(out);
        ok(run(c));
    };
    let deeper = d.join("deeper.exr");
    render(&["--max-depth", "3"], &deeper);
    // Another scene: the same file with a narrower field of view.
    let other = d.join("other-scene.exr");
    let narrower = d.join("narrower.toml");
    let text = std::fs::read_to_string(study()).unwrap();
    assert!(text.contains("fov_x    = 90.0"));
    std::fs::write(&narrower, text.replace("fov_x    = 90.0", "fov_x    = 80.0")).unwrap();
    let mut c = pathlab();
    c.arg("render").arg(&narrower).args(SIZE).args(["--spp", "4", "--variance", "--quiet"]).arg("-o").arg(&other);
    ok(run(c));
    let nan = d.join("nan.exr");
    let good = d.join("good.exr");
    render(&[], &good);
    // The first seed whose mutants forge a NaN into the red channel (which channels a plan
    // picks depends on the header's attributes).
    let m = (7..107)
        .find_map(|seed| mutants(&good, seed, PLAN).unwrap().into_iter().find(|m| m.label.starts_with("R[") && m.label.contains("NaN (forged)")))
        .expect("a NaN mutant");
    std::fs::write(&nan, &m.bytes).unwrap();
    for (file, expect) in [(&deeper, "max_depth 3"), (&nan, "non-finite"), (&other, "another scene")] {
        let mut c = pathlab();
        c.arg("study").arg(study()).arg("--out").arg(d.join("s")).args(["--size", "16x8", "--methods", "plain", "--spp", "1", "--time", "0.01", "--seeds", "1", "--quiet", "--reference"]).arg(file);
        let start = Instant::now();
        let r = run(c);
        assert_ne!(r.code, Some(0), "{}", r.stderr);
        assert!(r.stderr.contains(file.file_name().unwrap().to_str().unwrap()) && r.stderr.contains(expect), "{}", r.stderr);
        assert!(!r.stderr.contains("[1/4]") && !r.stderr.contains("adapter"), "refused only after starting: {}", r.stderr);
        assert!(start.elapsed() < Duration::from_secs(10));
    }
}

/// Each corruption the mutation study found passing into a wrong result, reproduced with 16x8
/// parts of the study scene: now refused, naming the file (and the pixel or the attribute).
#[test]
fn the_reported_findings_are_refused() {
    use pathlab::output::mutation::{duplicated, rewritten, with_value};
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let Originals { p0, p1, reference, test } = originals(d);
    let write = |name: &str, bytes: Vec<u8>| {
        let p = d.join(name);
        std::fs::write(&p, bytes).unwrap();
        p
    };
    let merge_of = |part: &Path| {
        let mut c = pathlab();
        c.arg("merge").arg(&p0).arg(part).arg("-o").arg(d.join("out.exr"));
        c
    };
    let merge_refuses = |what: &str, part: &Path, words: &[&str]| {
        let r = run(merge_of(part));
        assert_ne!(r.code, Some(0), "{what}: accepted: {}", r.stderr);
        assert!(r.stderr.contains(part.file_name().unwrap().to_str().unwrap()), "{what}: {}", r.stderr);
        for w in words {
            assert!(r.stderr.contains(w), "{what}: `{w}` missing from: {}", r.stderr);
        }
    };
    // Non-finite or impossible sums.
    merge_refuses("NaN sum", &write("nan.exr", with_value(&p1, "sum.R", 5, f32::NAN).unwrap()), &["pixel (5, 0)", "sum.R is NaN"]);
    merge_refuses("infinite sum", &write("inf.exr", with_value(&p1, "sum.G", 9, f32::INFINITY).unwrap()), &["pixel (9, 0)", "inf"]);
    merge_refuses("negative sum", &write("neg.exr", with_value(&p1, "sum.B", 3, -1.0).unwrap()), &["negative"]);
    merge_refuses("negative sum_sq", &write("negsq.exr", with_value(&p1, "sum_sq.R", 3, -1.0).unwrap()), &["negative"]);
    // Header numbers cut to 32 bits.
    merge_refuses("spp 2^32 + 2", &write("spp.exr", rewritten(&p1, &[("spp", "4294967298")]).unwrap()), &["pathlab:spp", "4294967298"]);
    merge_refuses("width 2^32 + 16", &write("width.exr", rewritten(&p1, &[("width", "4294967312")]).unwrap()), &["pathlab:width"]);
    merge_refuses("max_depth 2^32 + 2", &write("depth.exr", rewritten(&p1, &[("max_depth", "4294967298")]).unwrap()), &["pathlab:max_depth"]);
    // first_sample + spp past 2^64, and past 2^32.
    merge_refuses("first_sample 2^64 - 1", &write("wrap.exr", rewritten(&p1, &[("first_sample", "18446744073709551615")]).unwrap()), &["pathlab:first_sample"]);
    merge_refuses("range past 2^32", &write("past.exr", rewritten(&p1, &[("first_sample", "4294967293")]).unwrap()), &["beyond 2^32"]);
    // A single part's header: a second seed, an empty or a 100 kB scene_hash.
    let single = |what: &str, file: &Path, words: &[&str]| {
        let mut c = pathlab();
        c.arg("merge").arg(file).arg("-o").arg(d.join("single.exr"));
        let r = run(c);
        assert_ne!(r.code, Some(0), "{what}: accepted");
        assert!(r.stderr.contains(file.file_name().unwrap().to_str().unwrap()), "{what}: {}", r.stderr);
        for w in words {
            assert!(r.stderr.contains(w), "{what}: `{w}` missing from: {}", r.stderr);
        }
    };
    single("second seed", &write("seed2.exr", duplicated(&p0, "seed", "7").unwrap()), &["pathlab:seed appears more than once"]);
    single("empty scene_hash", &write("hash0.exr", rewritten(&p0, &[("scene_hash", " ")]).unwrap()), &["pathlab:scene_hash"]);
    let long = "a".repeat(100_000);
    single("100 kB scene_hash", &write("hashlong.exr", rewritten(&p0, &[("scene_hash", long.as_str())]).unwrap()), &["pathlab:scene_hash", "100000 bytes"]);
    // A part altered in transit, checksum unchanged: one flipped bit in the data.
    let mut bytes = std::fs::read(&p1).unwrap();
    let at = bytes.len() - 40;
    bytes[at] ^= 0x10;
    merge_refuses("flipped bit", &write("flip.exr", bytes), &["checksum"]);
    // Gaps name the part around them.
    let r = run({
        let mut c = pathlab();
        c.arg("merge").arg(&p1).arg("-o").arg(d.join("gap.exr"));
        c
    });
    assert!(r.stderr.contains("0..4") && r.stderr.contains("before") && r.stderr.contains("p1.exr"), "{}", r.stderr);
    // compare: a NaN pixel in either image, a NaN exposure, a garbage display.
    let compare = |t: &Path, r: &Path| {
        let mut c = pathlab();
        c.arg("compare").arg(t).arg(r).arg("--json");
        c
    };
    let nan_ref = write("nan-ref.exr", with_value(&reference, "G", 17, f32::NAN).unwrap());
    let nan_test = write("nan-test.exr", with_value(&test, "R", 33, f32::NAN).unwrap());
    for (what, t, r, file, words) in [
        ("NaN in the reference", &test, &nan_ref, &nan_ref, vec!["pixel (1, 1)", "non-finite G"]),
        ("NaN in the test image", &nan_test, &reference, &nan_test, vec!["pixel (1, 2)", "non-finite R"]),
    ] {
        let out = run(compare(t, r));
        assert_ne!(out.code, Some(0), "{what}: {}", out.stdout);
        assert!(out.stderr.contains(file.file_name().unwrap().to_str().unwrap()), "{what}: {}", out.stderr);
        for w in words {
            assert!(out.stderr.contains(w), "{what}: `{w}` missing from {}", out.stderr);
        }
    }
    for (name, key, value) in [("exposure.exr", "exposure", "nan"), ("gamma-abc.exr", "display", "gamma:abc"), ("gamma0.exr", "display", "gamma:0")] {
        let file = write(name, rewritten(&reference, &[(key, value)]).unwrap());
        let out = run(compare(&test, &file));
        assert_ne!(out.code, Some(0), "{name}: {}", out.stdout);
        assert!(out.stderr.contains(name) && out.stderr.contains(&format!("pathlab:{key}")), "{name}: {}", out.stderr);
    }
}
