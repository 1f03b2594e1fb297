//! `pathlab view` in a real window: an Xvfb server per test, the viewer on lavapipe, judged from
//! its screenshot (the window's framebuffer) and its `--log-stats` report (spp, rectangles of
//! the image, divider and plot in the screenshot's pixels).
//!
//! Needs `Xvfb` (Debian package `xvfb`); without it the tests say so and pass, except under CI
//! (`CI` set), where they fail. The viewer tests run one at a time (they share two cores).

use crate::common::{self, scratch_dir};

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

const WINDOW: (u32, u32) = (960, 600);

fn pathlab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pathlab"))
}

fn study() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.toml")
}


/// A private X server, stopped on drop.
struct Xvfb {
    child: Child,
    display: String,
    runtime_dir: common::ScratchDir,
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts Xvfb on a free display, or returns `None` (skip) when it is not installed outside CI.
fn xvfb(name: &str) -> Option<Xvfb> {
    let installed = Command::new("sh").args(["-c", "command -v Xvfb"]).output().is_ok_and(|o| o.status.success());
    if !installed {
        assert!(std::env::var_os("CI").is_none(), "Xvfb is required in CI (apt-get install xvfb)");
        common::not_run(name, "Xvfb is not installed (sudo apt-get install xvfb)");
        return None;
    }
    let number = (100..400)
        .find(|n| !Path::new(&format!("/tmp/.X11-unix/X{n}")).exists() && !Path::new(&format!("/tmp/.X{n}-lock")).exists())
        .expect("a free X display number");
    let child = Command::new("Xvfb")
        .arg(format!(":{number}"))
        .args(["-screen", "0", "1280x1024x24", "-nolisten", "tcp"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start Xvfb");
    let runtime_dir = scratch_dir(&format!("viewer-xdg-{name}"));
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&runtime_dir, std::fs::Permissions::from_mode(0o700)).unwrap();
    }
    let server = Xvfb { child, display: format!(":{number}"), runtime_dir };
    let socket = PathBuf::from(format!("/tmp/.X11-unix/X{number}"));
    let start = Instant::now();
    while !socket.exists() {
        assert!(start.elapsed() < Duration::from_secs(30), "Xvfb did not start");
        std::thread::sleep(Duration::from_millis(50));
    }
    Some(server)
}

fn viewer(x: &Xvfb) -> Command {
    let mut c = pathlab();
    c.env("DISPLAY", &x.display).env("XDG_RUNTIME_DIR", x.runtime_dir.as_os_str()).env_remove("WAYLAND_DISPLAY").env("WINIT_X11_SCALE_FACTOR", "1");
    c.arg("view").args(["--window", &format!("{}x{}", WINDOW.0, WINDOW.1), "--log-stats"]);
    c
}

fn report(out: &Output) -> serde_json::Value {
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "viewer failed: {:?}\n{stderr}", out.status);
    assert!(!stderr.contains("panicked"), "{stderr}");
    let line = stdout.lines().last().unwrap_or_else(|| panic!("no --log-stats line\n{stderr}"));
    serde_json::from_str(line).unwrap_or_else(|e| panic!("{e}: {line}"))
}

struct Screenshot {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

impl Screenshot {
    fn read(path: &Path) -> Screenshot {
        let img = image::open(path).unwrap().to_rgb8();
        Screenshot { width: img.width(), height: img.height(), rgb: img.into_raw() }
    }

    /// Pixels of the rectangle [x0, x1) x [y0, y1), rounded inwards.
    fn region(&self, r: [f64; 4]) -> Vec<[u8; 3]> {
        let (x0, y0) = (r[0].ceil() as u32, r[1].ceil() as u32);
        let (x1, y1) = ((r[2].floor() as u32).min(self.width), (r[3].floor() as u32).min(self.height));
        let mut out = Vec::new();
        for y in y0..y1 {
            for x in x0..x1 {
                let i = 3 * (y * self.width + x) as usize;
                out.push([self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]);
            }
        }
        out
    }
}

fn mean(pixels: &[[u8; 3]]) -> [f64; 3] {
    let n = pixels.len().max(1) as f64;
    std::array::from_fn(|c| pixels.iter().map(|p| p[c] as f64).sum::<f64>() / n)
}

/// Standard deviation of the pixels' luminance-ish average: 0 for a blank area.
fn spread(pixels: &[[u8; 3]]) -> f64 {
    let v: Vec<f64> = pixels.iter().map(|p| (p[0] as f64 + p[1] as f64 + p[2] as f64) / 3.0).collect();
    let m = v.iter().sum::<f64>() / v.len().max(1) as f64;
    (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / v.len().max(1) as f64).sqrt()
}

fn rect(v: &serde_json::Value) -> [f64; 4] {
    std::array::from_fn(|i| v[i].as_f64().unwrap())
}

#[test]
fn study_scene_converges_in_the_window() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let Some(x) = xvfb("converges") else { return };
    let dir = scratch_dir("viewer-converges");
    let shot = dir.join("shot.png");
    let out = viewer(&x).arg(study()).args(["--size", "256x128", "--frames", "60", "--screenshot"]).arg(&shot).output().unwrap();
    let r = report(&out);

    // The screenshot is the window's framebuffer: the window's size.
    let s = Screenshot::read(&shot);
    assert_eq!((s.width, s.height), WINDOW);
    assert_eq!(r["window"], serde_json::json!([WINDOW.0, WINDOW.1]));
    // Samples were added while the window ran.
    let spp = r["slots"][0]["spp"].as_u64().unwrap();
    assert!(spp >= 5, "only {spp} spp after 60 frames");
    assert!(r["frames"].as_u64().unwrap() >= 60);

    // The image area is not blank and has the colours of the scene: its mean within a broad
    // band of a headless render of the same scene, size and display transform.
    let area = s.region(rect(&r["image_rect"]));
    assert!(area.len() > 256 * 128 / 2, "image area of {} pixels", area.len());
    assert!(spread(&area) > 20.0, "the image area is (nearly) uniform: spread {}", spread(&area));
    let png = dir.join("render.png");
    let rendered = pathlab()
        .arg("render")
        .arg(study())
        .args(["--width", "256", "--height", "128", "--spp", "64", "--quiet", "-o"])
        .arg(dir.join("render.exr"))
        .arg("--png")
        .arg(&png)
        .output()
        .unwrap();
    assert!(rendered.status.success(), "{}", String::from_utf8_lossy(&rendered.stderr));
    let reference = Screenshot::read(&png);
    let reference = reference.region([0.0, 0.0, 256.0, 128.0]);
    let (a, b) = (mean(&area), mean(&reference));
    for c in 0..3 {
        assert!((a[c] - b[c]).abs() < 20.0, "channel {c}: window mean {:.1}, render mean {:.1}", a[c], b[c]);
    }
}

#[test]
fn split_view_with_reference_draws_both_halves_and_the_plot() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let Some(x) = xvfb("split") else { return };
    let dir = scratch_dir("viewer-split");
    let reference = dir.join("reference.exr");
    let made = pathlab()
        .arg("render")
        .arg(study())
        .args(["--width", "256", "--height", "128", "--spp", "256", "--seed", "99", "--quiet", "-o"])
        .arg(&reference)
        .output()
        .unwrap();
    assert!(made.status.success(), "{}", String::from_utf8_lossy(&made.stderr));
    let shot = dir.join("split.png");
    let out = viewer(&x)
        .arg(study())
        .args(["--size", "256x128", "--method", "best", "--compare", "plain", "--view", "rel-error", "--frames", "80"])
        .arg("--reference")
        .arg(&reference)
        .arg("--screenshot")
        .arg(&shot)
        .output()
        .unwrap();
    let r = report(&out);
    let s = Screenshot::read(&shot);

    // Both methods converged at once, scored against the reference (not estimated).
    let slots = r["slots"].as_array().unwrap();
    assert_eq!(slots.len(), 2);
    for slot in slots {
        assert!(slot["spp"].as_u64().unwrap() >= 2, "{slot}");
        assert_eq!(slot["estimated"], false, "{slot}");
        assert!(slot["psnr"].as_f64().is_some_and(f64::is_finite), "{slot}");
    }
    // Equal time, not equal samples: the render seconds agree within a frame or two.
    let (t0, t1) = (slots[0]["render_seconds"].as_f64().unwrap(), slots[1]["render_seconds"].as_f64().unwrap());
    assert!((t0 - t1).abs() < 0.25 * t0.max(t1), "render seconds {t0} and {t1}");

    // Both halves are drawn, each from its own method: in the relative-error view the plain
    // path tracer's half is much brighter (larger errors) than best's.
    let image = rect(&r["image_rect"]);
    let divider = r["divider_x"].as_f64().expect("a divider");
    assert!(divider > image[0] + 10.0 && divider < image[2] - 10.0);
    let left = s.region([image[0], image[1], divider - 3.0, image[3]]);
    let right = s.region([divider + 3.0, image[1], image[2], image[3]]);
    assert!(spread(&left) > 3.0 && spread(&right) > 10.0, "halves look blank: {} {}", spread(&left), spread(&right));
    let (l, rr) = (mean(&left), mean(&right));
    assert!(rr.iter().sum::<f64>() > 2.0 * l.iter().sum::<f64>(), "plain's error half {rr:?} vs best's {l:?}");

    // The plot panel is drawn: lines of two colours over the background.
    let plot = s.region(rect(&r["plot_rect"]));
    let background = [27u8, 27, 27];
    let painted = plot.iter().filter(|p| p.iter().zip(background).any(|(a, b)| a.abs_diff(b) > 40)).count();
    assert!(painted > 500, "the plot area has {painted} painted pixels");
}

#[test]
fn a_broken_scene_at_start_is_an_error_not_a_crash() {
    let dir = scratch_dir("viewer-broken");
    let scene = dir.join("broken.toml");
    std::fs::write(&scene, std::fs::read_to_string(study()).unwrap().replace("max_depth   = 2", "max_depth   = -2")).unwrap();
    // No display needed: the scene is checked before any window or device is opened.
    let out = pathlab().env_remove("DISPLAY").env_remove("WAYLAND_DISPLAY").arg("view").arg(&scene).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("broken.toml:15"), "{stderr}");
    assert!(stderr.contains("max_depth"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn without_a_display_it_says_so_and_suggests_render() {
    let out = pathlab().env_remove("DISPLAY").env_remove("WAYLAND_DISPLAY").arg("view").arg(study()).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no display") && stderr.contains("pathlab render"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn a_failed_reload_shows_the_error_and_keeps_the_last_image() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let Some(x) = xvfb("reload") else { return };
    let dir = scratch_dir("viewer-reload");
    let scene = dir.join("scene.toml");
    let good = std::fs::read_to_string(study()).unwrap();
    std::fs::write(&scene, &good).unwrap();
    let shot = dir.join("reload.png");
    let mut child = viewer(&x)
        .arg(&scene)
        .args(["--size", "256x128", "--frames", "150", "--screenshot"])
        .arg(&shot)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the viewer has loaded the scene and opened its window, then break the file.
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut seen = String::new();
    loop {
        let mut line = String::new();
        if stderr.read_line(&mut line).unwrap() == 0 {
            panic!("the viewer ended before it started rendering:\n{seen}");
        }
        seen.push_str(&line);
        if line.starts_with("pathlab view: ") {
            break;
        }
    }
    std::fs::write(&scene, good.replace("max_depth   = 2", "max_depth   = -2")).unwrap();
    let rest = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut stderr, &mut s);
        s
    });
    let status = child.wait().unwrap();
    let mut stdout = String::new();
    std::io::Read::read_to_string(&mut child.stdout.take().unwrap(), &mut stdout).unwrap();
    let out = Output { status, stdout: stdout.into_bytes(), stderr: (seen + &rest.join().unwrap()).into_bytes() };
    let r = report(&out);

    // The error is reported as `pathlab check` reports it (file:line, the field)...
    let error = r["scene_error"].as_str().expect("a scene error in the report");
    assert!(error.contains("scene.toml:15") && error.contains("max_depth"), "{error}");
    // ...drawn in the window over the last good image, which keeps converging.
    let s = Screenshot::read(&shot);
    let banner = s.rgb.chunks(3).filter(|p| p == &[150, 20, 20]).count();
    assert!(banner > 5000, "no error banner in the screenshot ({banner} banner pixels)");
    let image = s.region(rect(&r["image_rect"]));
    assert!(spread(&image) > 20.0, "the last good image is gone");
    assert!(r["slots"][0]["spp"].as_u64().unwrap() >= 5);
}

#[test]
fn a_technique_renders_in_the_window_and_is_offered_in_the_panel() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let Some(x) = xvfb("technique") else { return };
    let technique = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/techniques/sphere_area.wgsl");
    let out = viewer(&x)
        .arg(study())
        .args(["--size", "64x32", "--frames", "20", "--method", "mis", "--technique"])
        .arg(format!("light:{}", technique.display()))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    let r = report(&out);
    // Proven before the window opened; the method given uses it.
    assert!(stderr.contains("technique light:sphere_area: proven"), "{stderr}");
    assert_eq!(r["slots"][0]["method"], "mis+light=sphere_area", "{r}");
    assert!(r["slots"][0]["spp"].as_u64().unwrap() >= 1, "{r}");
}
