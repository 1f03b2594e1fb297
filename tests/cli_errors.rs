//! Bad input through the real binary: a non-zero exit, a message naming file, line and field,
//! no output file, and an existing output file left untouched. These run no GPU work: scenes
//! are refused before the adapter is opened.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::scratch_dir;

const VALID: &str = r#"[camera]
position = [0, 0, 1]
look_at = [0, 0, 0]
up = [0, 1, 0]
fov_x = 90

[render]
width = 8
height = 4
max_depth = 2

[materials.light]
diffuse = 0.5
emission = [4, 4, 4]

[materials.grey]
diffuse = [0.5, 0.5, 0.5]
specular = 0.2
glossiness = 20

[[spheres]]
center = [0, 0, -5]
radius = 1
material = "light"

[[planes]]
point = [0, -1, 0]
normal = [0, 1, 0]
material = "grey"
"#;

fn pathlab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pathlab"))
}

struct Case {
    name: &'static str,
    /// (text to replace, replacement) applied to VALID.
    edit: (&'static str, &'static str),
    /// 1-based line the error must point at.
    line: usize,
    /// The field the message must name.
    field: &'static str,
}

const CASES: &[Case] = &[
    Case { name: "malformed toml", edit: ("width = 8", "width = = 8"), line: 8, field: "render.width" },
    Case { name: "unknown field", edit: ("height = 4", "heigth = 4"), line: 9, field: "render.heigth" },
    Case { name: "unknown material", edit: ("material = \"light\"", "material = \"lihgt\""), line: 24, field: "spheres[0].material" },
    Case { name: "negative radius", edit: ("radius = 1", "radius = -1"), line: 23, field: "spheres[0].radius" },
    Case { name: "zero radius", edit: ("radius = 1", "radius = 0"), line: 23, field: "spheres[0].radius" },
    Case { name: "nan", edit: ("center = [0, 0, -5]", "center = [0, nan, -5]"), line: 22, field: "spheres[0].center" },
    Case { name: "infinity", edit: ("glossiness = 20", "glossiness = inf"), line: 19, field: "materials.grey.glossiness" },
    Case { name: "zero normal", edit: ("normal = [0, 1, 0]", "normal = [0, 0, 0]"), line: 28, field: "planes[0].normal" },
    Case { name: "negative colour", edit: ("diffuse = [0.5, 0.5, 0.5]", "diffuse = [0.5, -0.5, 0.5]"), line: 17, field: "materials.grey.diffuse" },
    Case { name: "fov out of range", edit: ("fov_x = 90", "fov_x = 180"), line: 5, field: "camera.fov_x" },
    Case { name: "both fovs", edit: ("fov_x = 90", "fov_x = 90\nfov_y = 40"), line: 6, field: "camera.fov_y" },
    Case { name: "zero width", edit: ("width = 8", "width = 0"), line: 8, field: "render.width" },
    Case { name: "zero max_depth", edit: ("max_depth = 2", "max_depth = 0"), line: 10, field: "render.max_depth" },
    Case { name: "emissive plane", edit: ("material = \"grey\"", "material = \"light\""), line: 29, field: "planes[0].material" },
    Case { name: "wrong type", edit: ("radius = 1", "radius = \"one\""), line: 23, field: "spheres[0].radius" },
    Case { name: "unknown transfer", edit: ("material = \"grey\"", "material = \"grey\"\n\n[display]\ntransfer = \"log\""), line: 32, field: "display.transfer" },
    Case { name: "gamma missing", edit: ("material = \"grey\"", "material = \"grey\"\n\n[display]\ntransfer = \"gamma\""), line: 32, field: "display.gamma" },
    Case { name: "gamma not positive", edit: ("material = \"grey\"", "material = \"grey\"\n\n[display]\ntransfer = \"gamma\"\ngamma = -1.6"), line: 33, field: "display.gamma" },
    Case { name: "gamma with srgb", edit: ("material = \"grey\"", "material = \"grey\"\n\n[display]\ngamma = 2.2"), line: 32, field: "display.gamma" },
];


fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn the_valid_scene_is_valid() {
    let dir = scratch_dir("cli-valid");
    let scene = write(&dir, "ok.toml", VALID);
    let out = pathlab().arg("check").arg(&scene).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn each_validation_error_names_file_line_and_field_and_writes_nothing() {
    let dir = scratch_dir("cli-errors");
    for case in CASES {
        assert!(VALID.contains(case.edit.0), "{}: edit does not apply", case.name);
        let scene = write(&dir, "bad.toml", &VALID.replacen(case.edit.0, case.edit.1, 1));
        let existing = dir.join("existing.exr");
        std::fs::write(&existing, b"previous good image").unwrap();
        let fresh = dir.join("fresh.exr");
        for (output, must_exist) in [(&existing, true), (&fresh, false)] {
            let out = pathlab().arg("render").arg(&scene).arg("-o").arg(output).arg("--quiet").output().unwrap();
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{}: exit status; stderr:\n{stderr}", case.name);
            let location = format!("{}:{}:", scene.display(), case.line);
            assert!(stderr.contains(&location), "{}: expected `{location}` in:\n{stderr}", case.name);
            assert!(stderr.contains(&format!("`{}`", case.field)), "{}: expected field `{}` in:\n{stderr}", case.name, case.field);
            if must_exist {
                assert_eq!(std::fs::read(output).unwrap(), b"previous good image", "{}: output touched", case.name);
            } else {
                assert!(!output.exists(), "{}: output written", case.name);
            }
        }
        let leftovers: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().filter(|e| e.file_name().to_string_lossy().ends_with(".tmp")).collect();
        assert!(leftovers.is_empty(), "{}: temporary files left behind", case.name);
    }
}

#[test]
fn warnings_do_not_fail() {
    let dir = scratch_dir("cli-warnings");
    let cases = [
        ("unused material", VALID.replace("[[planes]]", "[materials.spare]\ndiffuse = 0.1\n\n[[planes]]"), "never used"),
        ("not energy conserving", VALID.replace("specular = 0.2", "specular = 0.7"), "not energy conserving"),
        ("black scene", VALID.replace("emission = [4, 4, 4]", "emission = 0").replace("material = \"light\"", "material = \"grey\""), "will be black"),
    ];
    for (name, text, message) in cases {
        let scene = write(&dir, "warn.toml", &text);
        let out = pathlab().arg("check").arg(&scene).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{name}: {stderr}");
        assert!(stderr.contains("warning") && stderr.contains(message), "{name}: {stderr}");
    }
}

#[test]
fn bad_command_line_values_are_refused() {
    let dir = scratch_dir("cli-args");
    let scene = write(&dir, "ok.toml", VALID);
    for args in [&["--spp", "0"][..], &["--width", "0"], &["--time", "-1"], &["--method", "nonsense"]] {
        let out = pathlab().arg("render").arg(&scene).args(args).arg("-o").arg(dir.join("x.exr")).output().unwrap();
        assert!(!out.status.success(), "{args:?} accepted");
        assert!(!dir.join("x.exr").exists());
    }
    // `-o` names an EXR: another extension would get EXR bytes under a misleading name.
    let out = pathlab().arg("render").arg(&scene).arg("-o").arg(dir.join("x.png")).output().unwrap();
    assert!(!out.status.success() && !dir.join("x.png").exists());
    assert!(String::from_utf8_lossy(&out.stderr).contains("render writes OpenEXR; give a name ending in .exr"));
    let out = pathlab().arg("render").arg(dir.join("missing.toml")).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    // The cause once, not twice.
    assert!(stderr.contains("missing.toml") && stderr.matches("No such file").count() == 1, "{stderr}");
}

/// Output into a pipe closed early (`pathlab check s.toml | head -c 1`) ends the process
/// quietly, as for any Unix tool, not with a panic.
#[cfg(unix)]
#[test]
fn a_closed_output_pipe_is_not_a_panic() {
    use std::process::Stdio;
    let mut child = pathlab()
        .args(["check", concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/cornell_box.xml")])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
}
