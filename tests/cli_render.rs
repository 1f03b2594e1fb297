//! `pathlab render` end to end: default output name, EXR metadata, PNG preview, variance
//! channels, and Ctrl-C writing what it has with its true sample count.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use pathlab::output::read_exr;

use crate::common::scratch_dir;

fn pathlab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pathlab"))
}

fn study() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.toml")
}


fn meta<'a>(metadata: &'a [(String, String)], key: &str) -> &'a str {
    metadata.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str()).unwrap_or_else(|| panic!("no {key}"))
}

#[test]
fn default_output_metadata_png_and_variance() {
    let dir = scratch_dir("render-default");
    let out = pathlab()
        .current_dir(&dir)
        .arg("render")
        .arg(study())
        .args(["--width", "32", "--height", "16", "--spp", "8", "--method", "nee", "--seed", "5"])
        .args(["--png", "preview.png", "--variance", "--quiet"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("wrote study.exr"), "{stderr}");
    assert!(stderr.contains("adapter: "), "the chosen adapter is printed: {stderr}");
    // 32x16 is the scene's 2:1 and every flag given applies: nothing to note.
    assert!(!stderr.contains("note:"), "{stderr}");
    let (film, metadata) = read_exr(&dir.join("study.exr")).unwrap();
    assert_eq!((film.width, film.height, film.spp), (32, 16, 8));
    assert_eq!(meta(&metadata, "method"), "nee");
    assert_eq!(meta(&metadata, "sampler"), "independent");
    assert_eq!(meta(&metadata, "bsdf"), "uniform-sphere");
    assert_eq!(meta(&metadata, "lights"), "nee");
    assert_eq!(meta(&metadata, "seed"), "5");
    assert_eq!(meta(&metadata, "version"), pathlab::VERSION);
    assert!(meta(&metadata, "render_seconds").parse::<f64>().unwrap() > 0.0);
    // At least the camera rays: one per pixel sample.
    assert!(meta(&metadata, "rays").parse::<u64>().unwrap() >= 32 * 16 * 8);
    assert!(film.variance.iter().flatten().any(|&v| v > 0.0), "variance channels present");
    let png = image::open(dir.join("preview.png")).unwrap();
    assert_eq!((png.width(), png.height()), (32, 16));
}

/// A size of another aspect ratio, and flags the scene cannot use, are each noted once; the
/// render goes ahead.
#[test]
fn a_new_framing_and_flags_without_effect_are_noted_once() {
    let dir = scratch_dir("render-notes");
    let out = pathlab()
        .current_dir(&dir)
        .arg("render")
        .arg(study())
        .args(["--width", "16", "--height", "16", "--spp", "1", "--method", "mis", "--quiet"])
        .args(["--triangle-sampling", "solid-angle", "--microfacet-sampling", "ndf", "--lobe-selection", "fixed", "--sample-environment"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let notes: Vec<&str> = stderr.lines().filter(|l| l.starts_with("note: ")).collect();
    assert_eq!(notes.len(), 5, "{stderr}");
    // The study scene gives fov_x: at 16x16 the horizontal angle stays, more is seen vertically.
    assert!(notes.iter().any(|n| n.contains("16x16 has another aspect ratio than the scene's 1024x512")
        && n.contains("the horizontal field of view (fov_x)")
        && n.contains("more is seen above and below")), "{stderr}");
    assert!(notes.contains(&"note: --triangle-sampling has no effect: the scene has no emissive triangles"), "{stderr}");
    assert!(notes.contains(&"note: --microfacet-sampling has no effect: the scene has no rough conductor"), "{stderr}");
    assert!(notes.contains(&"note: --lobe-selection has no effect: the scene has no layered material (plastic)"), "{stderr}");
    assert!(notes.contains(&"note: --sample-environment has no effect: the scene's environment is black"), "{stderr}");
    let (film, _) = read_exr(&dir.join("study.exr")).unwrap();
    assert_eq!((film.width, film.height), (16, 16));
}

#[test]
fn same_seed_gives_identical_exr_pixels() {
    let dir = scratch_dir("render-seed");
    let run = |name: &str, seed: &str| {
        let out = pathlab()
            .current_dir(&dir)
            .arg("render")
            .arg(study())
            .args(["--width", "24", "--height", "12", "--spp", "4", "--seed", seed, "-o", name, "--quiet"])
            .output()
            .unwrap();
        assert!(out.status.success());
        read_exr(&dir.join(name)).unwrap().0
    };
    let (a, b, c) = (run("a.exr", "1"), run("b.exr", "1"), run("c.exr", "2"));
    let bits = |f: &pathlab::film::Film| f.mean.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a), bits(&b));
    assert_ne!(bits(&a), bits(&c));
}

/// SIGINT during a long render: the image so far is written, with its true spp, exit 130.
#[cfg(unix)]
#[test]
fn ctrl_c_writes_the_partial_image() {
    let dir = scratch_dir("render-sigint");
    let target = dir.join("partial.exr");
    std::fs::write(&target, b"old").unwrap();
    let mut child = pathlab()
        .arg("render")
        .arg(study())
        .args(["--width", "64", "--height", "32", "--time", "120", "--quiet", "-o"])
        .arg(&target)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the render is under way (the adapter line is printed before it starts).
    std::thread::sleep(Duration::from_secs(3));
    let start = Instant::now();
    let status = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(status.success());
    let exit = child.wait().unwrap();
    assert!(start.elapsed() < Duration::from_secs(60), "Ctrl-C took too long to act");
    assert_eq!(exit.code(), Some(130));
    let (film, metadata) = read_exr(&target).expect("a complete EXR replaced the old file");
    assert!(film.spp > 0);
    assert_eq!(meta(&metadata, "spp"), film.spp.to_string());
    assert!(film.is_finite());
}

/// With no Vulkan driver at all, the error says how to install lavapipe, and nothing is written.
#[test]
fn no_adapter_explains_how_to_install_lavapipe() {
    let dir = scratch_dir("render-noadapter");
    let out = pathlab()
        .current_dir(&dir)
        .env("VK_ICD_FILENAMES", dir.join("none.json"))
        .env("VK_DRIVER_FILES", dir.join("none.json"))
        .arg("render")
        .arg(study())
        .args(["--width", "8", "--height", "4", "--spp", "1", "--quiet"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("apt-get install -y mesa-vulkan-drivers"), "{stderr}");
    assert!(!dir.join("study.exr").exists());
}

/// `pathlab bench --json` produces one well-formed record per (method, size). Structure only:
/// no assertion on speed.
#[test]
fn bench_json_records() {
    let out = pathlab()
        .arg("bench")
        .arg(study())
        .args(["--methods", "plain,mis", "--size", "16x8", "--size", "8x8", "--seconds", "0.2", "--json"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let records: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    let records = records.as_array().expect("an array");
    assert_eq!(records.len(), 4);
    for r in records {
        for key in ["method", "width", "height", "max_depth", "spp", "pixel_samples_per_second", "wall_seconds", "first_frame_seconds"] {
            assert!(r.get(key).is_some(), "missing {key} in {r}");
        }
        assert!(r["spp"].as_u64().unwrap() > 0);
        assert!(r["pixel_samples_per_second"].as_f64().unwrap() > 0.0);
    }
}

/// Output files get the permissions the user's umask gives (0666 & !umask), not the
/// temporary file's 0600.
#[cfg(unix)]
#[test]
fn outputs_follow_the_umask() {
    use std::os::unix::fs::PermissionsExt;
    let dir = scratch_dir("render-umask");
    for (umask, mode) in [("022", 0o644), ("027", 0o640)] {
        let (exr, png) = (dir.join(format!("u{umask}.exr")), dir.join(format!("u{umask}.png")));
        let status = Command::new("sh")
            .arg("-c")
            .arg(format!("umask {umask}; exec \"$0\" \"$@\""))
            .arg(env!("CARGO_BIN_EXE_pathlab"))
            .arg("render")
            .arg(study())
            .args(["--width", "8", "--height", "4", "--spp", "1", "--quiet", "-o"])
            .arg(&exr)
            .arg("--png")
            .arg(&png)
            .status()
            .unwrap();
        assert!(status.success());
        for f in [&exr, &png] {
            assert_eq!(std::fs::metadata(f).unwrap().permissions().mode() & 0o777, mode, "{} under umask {umask}", f.display());
        }
    }
}

/// Headless commands print no windowing-system noise: Mesa's device-select layer would make
/// libwayland print "error: XDG_RUNTIME_DIR is invalid or not set" on a machine without a
/// session directory.
#[test]
fn headless_commands_print_no_windowing_noise() {
    let dir = scratch_dir("render-headless");
    for args in [vec!["adapters"], vec!["render", "--width", "8", "--height", "4", "--spp", "1", "--quiet", "-o", "h.exr"]] {
        let mut cmd = pathlab();
        cmd.current_dir(&dir).env_remove("XDG_RUNTIME_DIR").env_remove("NODEVICE_SELECT").arg(args[0]);
        if args[0] == "render" {
            cmd.arg(study());
        }
        let out = cmd.args(&args[1..]).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        assert!(!stderr.contains("XDG_RUNTIME_DIR"), "{args:?}: {stderr}");
        assert!(!stderr.contains("error"), "{args:?}: {stderr}");
    }
}
