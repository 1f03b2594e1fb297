//! Mitsuba 3 XML scenes: the same scene through TOML and through XML is one scene (one content
//! hash, one image bit for bit), `pathlab convert` writes a TOML file that loads as that scene,
//! the structure (includes, defaults, `--define`, `<ref>`) works as Mitsuba's, bad input is
//! refused with file, line, column, plugin and parameter, and mutated files never panic.
//! Deterministic: fixed seeds, no statistics.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::*;
use pathlab::method::Preset;
use pathlab::scene::{Bsdf, BsdfKind, Diagnostic, Scene, SceneError, Severity};

fn asset(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes").join(name)
}

fn pathlab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pathlab"))
}

#[test]
fn the_cornell_box_in_xml_is_the_cornell_box_in_toml_and_renders_bit_for_bit_the_same() {
    let toml = Scene::load(asset("cornell_box.toml")).unwrap();
    let xml = Scene::load(asset("cornell_box.xml")).unwrap();
    assert!(xml.warnings.is_empty(), "{:?}", xml.warnings);
    assert_eq!(xml.content_hash(), toml.content_hash());
    assert_eq!(xml.render.rr_depth, Some(5));
    assert!(xml.materials.iter().all(|m| !m.two_sided));
    let film = |scene: &Scene| {
        let mut s = scene.clone();
        (s.render.width, s.render.height) = (16, 16);
        bits(&render(&s, Preset::Mis.method(), 4, 9))
    };
    assert!(film(&toml) == film(&xml), "the XML and TOML Cornell boxes render differently");
}

/// Writes `files` into a fresh directory; returns it.
fn dir_with(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        if let Some(parent) = Path::new(name).parent() {
            std::fs::create_dir_all(dir.path().join(parent)).unwrap();
        }
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    dir
}

const TRIANGLE_OBJ: &str = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n";

/// A scene using includes, defaults, a `<ref>`, an OBJ in a subfolder, a sphere light, a
/// constant environment and a matrix transform.
fn structured_scene() -> tempfile::TempDir {
    let main = r#"<scene version="3.0.0">
    <default name="res" value="24"/>
    <default name="depth" value="3"/>
    <include filename="parts/materials.xml"/>
    <integrator type="path"><integer name="max_depth" value="$depth"/><integer name="rr_depth" value="2"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="50"/>
        <string name="fov_axis" value="diagonal"/>
        <transform name="to_world"><matrix value="-1 0 0 0  0 1 0 0  0 0 -1 4  0 0 0 1"/></transform>
        <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
        <film type="hdrfilm"><integer name="width" value="$res"/><integer name="height" value="16"/><rfilter type="box"/></film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="0.1"/></emitter>
    <shape type="obj">
        <string name="filename" value="meshes/tri.obj"/>
        <transform name="to_world"><rotate y="1" angle="30"/><translate value="0.5 0 0"/><scale value="2"/></transform>
        <ref id="grey"/>
    </shape>
    <shape type="sphere">
        <point name="center" x="0" y="2" z="1"/>
        <float name="radius" value="0.25"/>
        <emitter type="area"><rgb name="radiance" value="5, 4, 3"/></emitter>
    </shape>
</scene>"#;
    let materials = r#"<scene version="3.0.0">
    <bsdf type="twosided" id="grey"><bsdf type="diffuse"><rgb name="reflectance" value="0.4"/></bsdf></bsdf>
</scene>"#;
    dir_with(&[("scene.xml", main), ("parts/materials.xml", materials), ("meshes/tri.obj", TRIANGLE_OBJ)])
}

#[test]
fn the_veach_scene_loads_as_written() {
    let s = Scene::load(asset("veach_mis.xml")).unwrap();
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let rough: Vec<f64> = s.materials.iter().filter_map(|m| match &m.bsdf { Bsdf::RoughConductor(r) => Some(r.roughness.alpha), _ => None }).collect();
    assert_eq!(rough.len(), 4);
    for alpha in [0.01, 0.05, 0.1, 0.25] {
        assert!(rough.contains(&alpha), "{rough:?}");
    }
    assert!(s.materials.iter().filter(|m| m.bsdf_kind() != BsdfKind::Phong).all(|m| m.two_sided));
    assert_eq!((s.spheres.len(), s.light_spheres().len(), s.num_triangles()), (3, 3, 4 * 12 + 2 * 2));
    assert_eq!((s.render.width, s.render.height, s.render.max_depth, s.render.rr_depth), (1280, 720, 3, None));
    // The camera looks down -x from (28.28, 3.5, 0), up +y: not mirrored.
    assert!((s.camera.look_at - s.camera.position).normalize().dot(glam::DVec3::NEG_X) > 0.999999);
}

#[test]
fn includes_defaults_defines_and_refs_work_as_in_mitsuba_and_convert_keeps_the_scene() {
    let dir = structured_scene();
    let path = dir.path().join("scene.xml");
    let s = Scene::load(&path).unwrap();
    assert_eq!((s.render.width, s.render.height, s.render.max_depth, s.render.rr_depth, s.render.spp), (24, 16, 3, Some(2), Some(16)));
    assert_eq!(s.render.environment.to_array(), [0.1; 3]);
    assert_eq!((s.spheres.len(), s.meshes.len(), s.num_triangles()), (1, 1, 1));
    // The twosided grey; the emitting sphere's default BSDF (Mitsuba's for an emitter: diffuse
    // black, one-sided) with its emission.
    let kd = |m: &pathlab::scene::Material| m.bsdf.as_phong().map_or(-1.0, |p| p.diffuse.x);
    assert!(s.materials.iter().any(|m| m.two_sided && kd(m) == 0.4));
    assert!(s.materials.iter().any(|m| !m.two_sided && kd(m) == 0.0 && m.emission.x == 5.0));
    // The matrix camera: at (0, 0, 4) looking down -z; a diagonal field of view.
    assert_eq!(s.camera.position.to_array(), [0.0, 0.0, 4.0]);
    assert!((s.camera.look_at - glam::DVec3::new(0.0, 0.0, 3.0)).length() < 1e-12);
    // The rule is kept (another size reframes as Mitsuba would); at the film's size it is this
    // horizontal angle.
    assert_eq!(s.camera.fov().unwrap(), pathlab::scene::Fov::Diagonal(50.0));
    let pathlab::scene::Fov::X(fx) = s.camera.fov().unwrap().resolve(24, 16) else { panic!("{:?}", s.camera.fov().unwrap()) };
    let expected = 2.0 * ((25f64.to_radians()).tan() * 24.0 / (24f64 * 24.0 + 16.0 * 16.0).sqrt()).atan().to_degrees();
    assert!((fx - expected).abs() < 1e-9, "{fx} vs {expected}");
    // --define overrides a default, like Mitsuba's -D.
    let defined = Scene::load_with(&path, &[("res".into(), "8".into()), ("depth".into(), "5".into())]).unwrap();
    assert_eq!((defined.render.width, defined.render.max_depth), (8, 5));

    // convert: to a file elsewhere (the OBJ named relative to it where below it, else in full),
    // which loads as the same scene.
    let out = dir.path().join("converted.toml");
    let r = pathlab().arg("convert").arg(&path).arg("-o").arg(&out).output().unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("file = \"meshes/tri.obj\""), "{text}");
    assert_eq!(Scene::load(&out).unwrap().content_hash(), s.content_hash());
    let elsewhere = tempfile::tempdir().unwrap();
    let out = elsewhere.path().join("c.toml");
    let r = pathlab().args(["convert", "--define", "res=8"]).arg(&path).arg("-o").arg(&out).output().unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    // With --define res=8 (height 16 stays) but depth 3: a scene of its own.
    let res8 = Scene::load_with(&path, &[("res".into(), "8".into())]).unwrap();
    let back = Scene::load(&out).unwrap();
    assert_eq!(back.content_hash(), res8.content_hash());
    assert!(back.meshes[0].source.starts_with('/'), "a file outside the output's folder is named in full: {}", back.meshes[0].source);
}

/// A small valid scene, with `extra` inside <scene> after the sensor.
fn small(extra: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/><rfilter type="box"/></film>
    </sensor>
    <bsdf type="diffuse" id="grey"><rgb name="reflectance" value="0.5"/></bsdf>
    <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
{extra}
</scene>
"#
    )
}

/// The first error of a scene that must be refused, with the file it was written to.
fn refused(text: &str) -> (Diagnostic, PathBuf) {
    let dir = dir_with(&[("s.xml", text), ("tri.obj", TRIANGLE_OBJ)]);
    let path = dir.path().join("s.xml");
    match Scene::load(&path) {
        Err(SceneError::Invalid(d)) => (d.into_iter().find(|d| d.severity == Severity::Error).expect("an error"), path),
        Err(e) => panic!("not a diagnostic: {e}"),
        Ok(_) => panic!("accepted:\n{text}"),
    }
}

/// Line and column (1-based) of the first occurrence of `needle` in `text`.
fn position_of(text: &str, needle: &str) -> (usize, usize) {
    let at = text.find(needle).unwrap_or_else(|| panic!("{needle} not in the scene"));
    let line = text[..at].matches('\n').count() + 1;
    let column = at - text[..at].rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, column)
}

#[test]
fn bad_xml_is_refused_with_file_line_column_plugin_and_parameter() {
    // (scene, where the error must point, what it must say)
    let cases: Vec<(String, &str, &str)> = vec![
        (small("<shape type=\"obj\"><string name=\"filename\" value=\"tri.obj\"/>\n</scene>"), "", "malformed XML"),
        (small("<shape type=\"cube\"><ref id=\"nope\"/></shape>"), "<ref id=\"nope\"/>", "names no object of the scene (defined: grey)"),
        (small("<shape type=\"sphere\"><float name=\"radius\" value=\"$r\"/></shape>"), "$r", "`$r` has no value"),
        (small("<shape type=\"obj\"><ref id=\"grey\"/></shape>"), "<shape type=\"obj\">", "needs <string name=\"filename\">"),
        (small("<shape type=\"cube\"><transform name=\"to_world\"><scale value=\"1, 0, 1\"/></transform></shape>"), "<scale value=\"1, 0, 1\"/>", "singular"),
        (small("<bsdf type=\"hair\" id=\"p\"/>"), "<bsdf type=\"hair\"", "<bsdf type=\"hair\"> is not supported (pathlab has diffuse, modphong, conductor, roughconductor, dielectric, plastic, roughdielectric, thindielectric, null, polarizer, roughplastic, principled, pplastic, principledthin, twosided, mask, blendbsdf, normalmap, bumpmap)"),
        (small("<bsdf type=\"diffuse\" id=\"d\"><float name=\"roughness\" value=\"1\"/></bsdf>"), "<float name=\"roughness\"", "`roughness` of <bsdf type=\"diffuse\"> is not supported (pathlab reads: reflectance)"),
        (small("<shape type=\"sphere\"><float name=\"radius\" value=\"nan\"/></shape>"), "nan\"", "must be a finite number > 0 (got NaN)"),
        (small("<shape type=\"sphere\"><float name=\"radius\" value=\"-1\"/></shape>"), "-1\"", "must be a finite number > 0 (got -1)"),
        (small("<shape type=\"ellipsoids\"/>"), "<shape type=\"ellipsoids\"", "<shape type=\"ellipsoids\"> is not supported (pathlab has obj, ply, serialized, rectangle, cube, sphere, disk, cylinder, linearcurve, bsplinecurve, sdfgrid, shapegroup, instance)"),
        (small("<emitter type=\"sunsky\"/>"), "<emitter type=\"sunsky\"", "not supported (pathlab has area, constant, envmap, point, spot, directional, projector)"),
        (small("<integrator type=\"bdpt\"/>"), "<integrator type=\"bdpt\"", "not supported (pathlab is a unidirectional path tracer"),
        (small("<shape type=\"cube\"><rgb name=\"radiance\" value=\"1, 2\"/></shape>"), "1, 2", "needs 3 (or 1) numbers, got 2"),
        (small("<bsdf type=\"roughconductor\" id=\"r\"><float name=\"alpha\" value=\"0\"/></bsdf>"), "0\"/></bsdf>", "`alpha` of <bsdf type=\"roughconductor\"> must be a finite number > 0 (got 0)"),
        (small("<bsdf type=\"roughconductor\" id=\"r\"><float name=\"alpha\" value=\"NaN\"/></bsdf>"), "NaN", "must be a finite number > 0 (got NaN)"),
        (small("<bsdf type=\"conductor\" id=\"r\"><string name=\"material\" value=\"Gold\"/></bsdf>"), "Gold", "unknown conductor \"Gold\" (Mitsuba's named conductors: Ag, Al,"),
        (small("<bsdf type=\"roughconductor\" id=\"r\"><rgb name=\"eta\" value=\"0.2\"/><string name=\"material\" value=\"Cu\"/></bsdf>"), "Cu", "give either `material` or `eta` and `k`, not both"),
        (small("<bsdf type=\"roughconductor\" id=\"r\"><string name=\"distribution\" value=\"phong\"/></bsdf>"), "phong\"", "unknown distribution \"phong\""),
        (small("").replace("value=\"45\"", "value=\"inf\""), "inf\"", "`fov` must be a finite angle in (0, 180) degrees (got inf)"),
        (small("").replace("value=\"45\"", "value=\"180\""), "180\"", "`fov` must be a finite angle in (0, 180) degrees (got 180)"),
        (small("<shape type=\"cube\"><transform name=\"to_world\"><rotate y=\"0\" angle=\"-17\"/></transform></shape>"), "<rotate y=\"0\"", "<rotate> has a zero axis"),
    ];
    for (text, at, message) in &cases {
        let (d, path) = refused(text);
        assert_eq!(d.file, path, "{d}");
        assert!(d.message.contains(message), "expected `{message}` in: {d}");
        assert!(d.line >= 1 && d.column >= 1, "no position: {d}");
        if !at.is_empty() {
            assert_eq!((d.line, d.column), position_of(text, at), "wrong position for `{message}`: {d}");
        }
    }
    // At the command line: a non-zero exit, the message as `file:line:column: error: ...`.
    let dir = dir_with(&[("s.xml", &cases[1].0)]);
    let r = pathlab().arg("check").arg(dir.path().join("s.xml")).output().unwrap();
    let stderr = String::from_utf8_lossy(&r.stderr);
    let (line, column) = position_of(&cases[1].0, "<ref id=\"nope\"/>");
    assert_eq!(r.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains(&format!("s.xml:{line}:{column}: error: `id`: <ref id=\"nope\">")), "{stderr}");
    // A --define with no effect is said, not ignored.
    let d = Scene::load_with(asset("cornell_box.xml"), &[("nothing".into(), "1".into())]).unwrap();
    assert!(d.warnings.iter().any(|w| w.message.contains("no effect")), "{:?}", d.warnings);
}

#[test]
fn settings_that_keep_the_expected_image_are_accepted_with_a_warning() {
    let text = small("").replace("<rfilter type=\"box\"/>", "<rfilter type=\"gaussian\"/>").replace(
        "<float name=\"fov\" value=\"45\"/>",
        "<float name=\"fov\" value=\"45\"/><float name=\"near_clip\" value=\"0.1\"/><sampler type=\"stratified\"><integer name=\"sample_count\" value=\"4\"/></sampler>",
    );
    let dir = dir_with(&[("s.xml", &text)]);
    let s = Scene::load(dir.path().join("s.xml")).unwrap();
    let said: Vec<&str> = s.warnings.iter().map(|w| w.message.as_str()).collect();
    for expected in ["pathlab's pixel filter is a box", "pathlab does not clip", "pathlab's sampler is chosen with --method"] {
        assert!(said.iter().any(|m| m.contains(expected)), "no warning `{expected}` in {said:#?}");
    }
    assert_eq!(s.render.spp, Some(4));

    // A sampler defined at the top level with an id and taken by <ref> in the sensor (mitsuba-data's
    // sampler documentation scenes), and a film `banner` (Mitsuba 3 reads and ignores it).
    let text = small("<sampler type=\"independent\" id=\"s16\"><integer name=\"sample_count\" value=\"16\"/></sampler>")
        .replace("<float name=\"fov\" value=\"45\"/>", "<float name=\"fov\" value=\"45\"/><ref id=\"s16\"/>")
        .replace("<integer name=\"width\" value=\"8\"/>", "<integer name=\"width\" value=\"8\"/><boolean name=\"banner\" value=\"false\"/>");
    let dir = dir_with(&[("s.xml", &text)]);
    let s = Scene::load(dir.path().join("s.xml")).unwrap();
    assert_eq!(s.render.spp, Some(16));
    assert!(s.warnings.iter().any(|w| w.field == "banner" && w.message.contains("ignored")), "{:?}", s.warnings);
    // Without an id it is still misplaced.
    let (d, _) = refused(&small("<sampler type=\"independent\"/>"));
    assert!(d.message.contains("<sampler> belongs inside the <sensor>"), "{d}");
}

/// Seeded mutations of the Cornell box's XML: characters deleted, duplicated or replaced,
/// attribute values replaced by bad ones, elements cut, the file truncated. Each must load or
/// be refused, never panic, and a refusal must name the file and a line.
#[test]
fn mutated_xml_never_panics_and_is_refused_by_file_and_line() {
    let original = std::fs::read_to_string(asset("cornell_box.xml")).unwrap();
    let mut state = 0x9e3779b97f4a7c15u64;
    let mut next = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n.max(1) as u64) as usize
    };
    let bad_values = ["nan", "-1", "0", "", "1e999", "abc", "$undefined", "1, 2", "0 0 0 0", "-0", "\u{fffd}"];
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.xml");
    let (mut refused, mut loaded) = (0, 0);
    for k in 0..400 {
        let mut text = original.clone();
        let boundary = |t: &str, mut i: usize| {
            while !t.is_char_boundary(i) {
                i -= 1;
            }
            i
        };
        match k % 5 {
            0 => {
                let i = boundary(&text, next(text.len()));
                text.truncate(i);
            }
            1 => {
                let i = boundary(&text, next(text.len()));
                let j = boundary(&text, (i + 1 + next(8)).min(text.len()));
                text.replace_range(i..j, "");
            }
            2 => {
                let i = boundary(&text, next(text.len()));
                let c = ['<', '>', '"', '/', '$', '=', ' ', '9'][next(8)];
                text.insert(i, c);
            }
            3 => {
                // An attribute value replaced.
                let values: Vec<usize> = text.match_indices("value=\"").map(|(i, _)| i + 7).collect();
                let start = values[next(values.len())];
                let end = start + text[start..].find('"').unwrap();
                text.replace_range(start..end, bad_values[next(bad_values.len())]);
            }
            _ => {
                // A line removed.
                let lines: Vec<&str> = text.lines().collect();
                let cut = next(lines.len());
                text = lines.iter().enumerate().filter(|(i, _)| *i != cut).map(|(_, l)| *l).collect::<Vec<_>>().join("\n");
            }
        }
        std::fs::write(&path, &text).unwrap();
        let result = std::panic::catch_unwind(|| Scene::load(&path));
        match result {
            Err(_) => panic!("mutant {k} panicked:\n{text}"),
            Ok(Ok(_)) => loaded += 1,
            Ok(Err(SceneError::Invalid(d))) => {
                refused += 1;
                let e = d.iter().find(|d| d.severity == Severity::Error).unwrap_or_else(|| panic!("mutant {k}: refused without an error: {d:?}"));
                assert!(e.file == path && e.line >= 1, "mutant {k}: the error names no file and line: {e}\n{text}");
            }
            Ok(Err(e)) => panic!("mutant {k}: {e}"),
        }
    }
    println!("{refused} mutants refused, {loaded} loaded");
    assert!(refused > 200, "only {refused} of 400 mutants refused: the mutations are too weak");
}

/// Mitsuba's file resolver and camera defaults, which published scenes rely on (mitsuba-data's
/// docs scenes, Mitsuba's tutorials, Bitterli's scenes): `<path value>` puts a folder in front of
/// the search for meshes (relative to the file that says it); a mesh named in an included file is
/// found from the main file's folder as Mitsuba finds it (and beside the include, as before); a
/// missing one is refused naming every folder searched. A camera without `fov` has Mitsuba's
/// 50mm focal length, `focal_length="35mm"` its diagonal field of view on a 36 x 24 mm film;
/// `focus_distance` is ignored with a warning; a camera matrix orthogonal to 2e-5 (six digits) is
/// accepted, one off by 1e-2 refused. A `<ref>` may name an object defined after it, and a
/// named top-level area emitter is taken by the shapes that refer to it. `moment` is read as the
/// integrator it wraps.
#[test]
fn paths_focal_lengths_and_published_camera_matrices_are_read_as_mitsuba_reads_them() {
    use pathlab::scene::Fov;
    let mesh = r#"<shape type="obj"><string name="filename" value="tri.obj"/><ref id="grey"/></shape>"#;
    // <path>: the mesh lives in assets/, the scene names it bare.
    let with_path = small(&format!("<path value=\"assets\"/>{mesh}"));
    let dir = dir_with(&[("s.xml", &with_path), ("assets/tri.obj", TRIANGLE_OBJ)]);
    let s = Scene::load(dir.path().join("s.xml")).unwrap();
    assert_eq!(s.meshes.len(), 2, "the rectangle and the OBJ");
    // An include in parts/ names meshes/tri.obj, which lies beside the main file.
    let main = small("<include filename=\"parts/shapes.xml\"/>");
    let part = format!("<scene version=\"3.0.0\"><shape type=\"obj\"><string name=\"filename\" value=\"meshes/tri.obj\"/></shape></scene>");
    let dir = dir_with(&[("s.xml", &main), ("parts/shapes.xml", &part), ("meshes/tri.obj", TRIANGLE_OBJ)]);
    assert_eq!(Scene::load(dir.path().join("s.xml")).unwrap().meshes.len(), 2);
    // An include's own <path> and <include> name folders and files of the main file's folder
    // (Mitsuba 3.9.1's parser tries beside the including file, then its resolver, which holds
    // the main file's folder: mitsuba-data's docs scenes' include/ files say
    // <path value="../../common"/>, its participating-media test scenes' include
    // "include/preamble.xml"). Before 2026-12-05 pathlab looked beside the included file only.
    let part = "<scene version=\"3.0.0\"><path value=\"assets\"/><include filename=\"parts/more.xml\"/></scene>";
    let more = "<scene version=\"3.0.0\"><shape type=\"obj\"><string name=\"filename\" value=\"tri.obj\"/></shape></scene>";
    let dir = dir_with(&[("s.xml", &main), ("parts/shapes.xml", part), ("parts/more.xml", more), ("assets/tri.obj", TRIANGLE_OBJ)]);
    assert_eq!(Scene::load(dir.path().join("s.xml")).unwrap().meshes.len(), 2);
    // Missing: every folder searched is named.
    let dir = dir_with(&[("s.xml", &with_path.replace("tri.obj", "gone.obj")), ("assets/tri.obj", TRIANGLE_OBJ)]);
    let e = Scene::load(dir.path().join("s.xml")).unwrap_err().to_string();
    assert!(e.contains("s.xml:") && e.contains("mesh file \"gone.obj\" not found (searched ") && e.contains("assets/"), "{e}");
    let (d, _) = refused(&small("<path value=\"nowhere\"/>"));
    assert!(d.message.contains("<path>: folder") && d.message.contains("not found"), "{d}");

    // Focal lengths: Mitsuba's default 50mm, and 35mm, as diagonal fields of view.
    let no_fov = small("").replace("<float name=\"fov\" value=\"45\"/>", "<float name=\"focus_distance\" value=\"3\"/>");
    let dir = dir_with(&[("s.xml", &no_fov)]);
    let s = Scene::load(dir.path().join("s.xml")).unwrap();
    let diagonal = |mm: f64| 2.0 * (36.0f64.hypot(24.0) / (2.0 * mm)).atan().to_degrees();
    assert!(matches!(s.camera.fov().unwrap(), Fov::Diagonal(d) if (d - diagonal(50.0)).abs() < 1e-12), "{:?}", s.camera.fov().unwrap());
    assert!(s.warnings.iter().any(|w| w.field == "focus_distance" && w.message.contains("pinhole")), "{:?}", s.warnings);
    let dir = dir_with(&[("s.xml", &small("").replace("<float name=\"fov\" value=\"45\"/>", "<string name=\"focal_length\" value=\"35mm\"/>"))]);
    let s = Scene::load(dir.path().join("s.xml")).unwrap();
    assert!(matches!(s.camera.fov().unwrap(), Fov::Diagonal(d) if (d - diagonal(35.0)).abs() < 1e-12), "{:?}", s.camera.fov().unwrap());
    let (d, _) = refused(&small("").replace("<float name=\"fov\" value=\"45\"/>", "<float name=\"fov\" value=\"45\"/><string name=\"focal_length\" value=\"35mm\"/>"));
    assert!(d.message.contains("either `fov` or `focal_length`"), "{d}");
    let (d, _) = refused(&small("").replace("<float name=\"fov\" value=\"45\"/>", "<string name=\"focal_length\" value=\"wide\"/>"));
    assert!(d.message.contains("<x>mm"), "{d}");

    // A camera matrix written to six digits (Bitterli's veach-bidir), and one that shears.
    let matrix = |m: &str| {
        small("").replace(
            "<transform name=\"to_world\"><lookat origin=\"0, 0, 5\" target=\"0, 0, 0\" up=\"0, 1, 0\"/></transform>",
            &format!("<transform name=\"to_world\"><matrix value=\"{m}\"/></transform>"),
        )
    };
    let six_digits = "-0.999914 0.000835626 0.013058 -0.587317 -5.82126e-011 0.997959 -0.063863 2.7623 -0.0130847 -0.0638576 -0.997873 9.71429 0 0 0 1";
    let dir = dir_with(&[("s.xml", &matrix(six_digits))]);
    let s = Scene::load(dir.path().join("s.xml")).unwrap();
    // Not quite orthogonal: the camera's frame moves its axes (by 3.1e-8 rad, measured), which
    // `check` reports; a look-at is exact.
    let moved = s.translation.sensor_correction.expect("a correction");
    assert!(moved > 1e-9 && moved < 1e-4, "{moved}");
    let out = pathlab().arg("check").arg(dir.path().join("s.xml")).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("sensor to_world: orthonormalised, its axes moved by at most"), "{stdout}");
    let dir = dir_with(&[("s.xml", &small(""))]);
    assert_eq!(Scene::load(dir.path().join("s.xml")).unwrap().translation.sensor_correction, None);
    let (d, _) = refused(&matrix("1 0.01 0 0 0 1 0 0 0 0 1 5 0 0 0 1"));
    assert!(d.message.contains("must be a rotation and translation"), "{d}");

    // A shape taking, by a forward <ref>, a named top-level area emitter defined after it
    // (mitsuba-data's cbox-rgb.xml): the shape emits.
    let forward = small(r#"<shape type="cube"><ref id="lamp"/><ref id="grey"/></shape>
        <emitter type="area" id="lamp"><rgb name="radiance" value="3"/></emitter>"#);
    let dir = dir_with(&[("s.xml", &forward)]);
    let s = Scene::load(dir.path().join("s.xml")).unwrap();
    assert_eq!(s.materials.iter().filter(|m| m.emission == glam::DVec3::splat(3.0)).count(), 1, "{:?}", s.materials);
    let (d, _) = refused(&small(r#"<emitter type="area"><rgb name="radiance" value="3"/></emitter>"#));
    assert!(d.message.contains("belongs inside the <shape> that emits"), "{d}");
    // Mitsuba's test scenes wrap `path` in `moment`: read as the integrator it wraps.
    let moment = small(r#"<integrator type="moment"><integrator type="path"><integer name="max_depth" value="3"/></integrator></integrator>"#);
    let dir = dir_with(&[("s.xml", &moment)]);
    let s = Scene::load(dir.path().join("s.xml")).unwrap();
    assert_eq!(s.render.max_depth, 3);
    assert!(s.warnings.iter().any(|w| w.message.contains("is read as the integrator it wraps")), "{:?}", s.warnings);
    let (d, _) = refused(&small(r#"<integrator type="moment"/>"#));
    assert!(d.message.contains("must wrap exactly one <integrator>"), "{d}");
    // A constant emitter without radiance has Mitsuba's default, 1.
    let dir = dir_with(&[("s.xml", &small(r#"<emitter type="constant"/>"#))]);
    assert_eq!(Scene::load(dir.path().join("s.xml")).unwrap().render.environment, glam::DVec3::ONE);
}

/// Mitsuba gives a shape without a BSDF its default diffuse, but a black one where the shape
/// emits (`Shape::Shape`): an area light reflects nothing unless given a BSDF.
#[test]
fn an_area_light_without_a_bsdf_reflects_nothing_as_in_mitsuba() {
    let text = small("<shape type=\"cube\"/>");
    let dir = dir_with(&[("s.xml", &text)]);
    let s = Scene::load(dir.path().join("s.xml")).unwrap();
    let diffuse = |emits: bool| {
        let m = s.materials.iter().find(|m| m.is_emissive() == emits).expect("the material");
        match &m.bsdf {
            Bsdf::Phong(p) => p.diffuse.to_array(),
            other => panic!("{other:?}"),
        }
    };
    assert_eq!(diffuse(true), [0.0; 3], "the emitting rectangle");
    assert_eq!(diffuse(false), [0.5; 3], "the plain cube");

    // An area emitter without `radiance` emits Mitsuba 3.9.1's default, 1 (`mi.traverse` of
    // one gives `emitter.radiance.value` [1]).
    let text = small("<shape type=\"cube\"><emitter type=\"area\"/></shape>");
    let dir = dir_with(&[("s.xml", &text)]);
    let s = Scene::load(dir.path().join("s.xml")).unwrap();
    assert!(s.materials.iter().filter(|m| m.is_emissive()).all(|m| m.emission.to_array() == [1.0; 3]), "{:?}", s.materials);
    assert!(s.meshes.len() == 2 && s.meshes.iter().all(|m| s.materials[m.material].is_emissive()), "both the rectangle and the cube emit");
    // A textured radiance: read on a mesh (a checkerboard of Mitsuba's default colours, 0.4 and
    // 0.2, mean 0.3), refused on a sphere (emission textures are looked up on triangles alone).
    let text = small("<shape type=\"cube\"><emitter type=\"area\"><texture type=\"checkerboard\" name=\"radiance\"/></emitter></shape>");
    let dir = dir_with(&[("s.xml", &text)]);
    let s = Scene::load(dir.path().join("s.xml")).unwrap();
    assert!(s.materials.iter().any(|m| m.emission_texture.is_some() && (m.emission - glam::DVec3::splat(0.3)).abs().max_element() < 1e-12), "{:?}", s.materials);
    let text = small("<shape type=\"sphere\"><emitter type=\"area\"><texture type=\"checkerboard\" name=\"radiance\"/></emitter></shape>");
    let (d, _) = refused(&text);
    assert!(d.message.contains("supports on triangle meshes"), "{d}");
    assert_eq!(d.line, position_of(&text, "<shape type=\"sphere\"").0, "{d}");
}

/// Mitsuba's `instance`s of a `shapegroup` are flattened into world-space shapes, each with
/// the instance's transform after its own: the same meshes and spheres, to the last bit, as the
/// file written without instancing with the composed transforms; `check` counts them. Groups
/// with emitters, nested groups or instances, and instances without one group are refused, as
/// Mitsuba refuses them.
#[test]
fn instances_of_shape_groups_are_flattened_as_mitsuba_places_them() {
    let obj = |to_world: &str| format!(r#"<shape type="obj"><string name="filename" value="tri.obj"/><ref id="grey"/><transform name="to_world">{to_world}</transform></shape>"#);
    let sphere = |to_world: &str| format!(r#"<shape type="sphere"><float name="radius" value="0.5"/><ref id="grey"/>{to_world}</shape>"#);
    let (a, b) = (r#"<scale value="2"/><translate y="3"/>"#, r#"<rotate z="1" angle="90"/><translate x="-4"/>"#);
    let grouped = small(&format!(
        r#"<shape type="shapegroup" id="pair">{}{}</shape>
        <shape type="instance"><ref id="pair"/><transform name="to_world">{a}</transform></shape>
        <shape type="instance"><ref id="pair"/><transform name="to_world">{b}</transform></shape>"#,
        obj(r#"<translate x="1"/>"#),
        sphere("")
    ));
    let flat = small(&format!(
        "{}{}{}{}",
        obj(&format!(r#"<translate x="1"/>{a}"#)),
        sphere(&format!(r#"<transform name="to_world">{a}</transform>"#)),
        obj(&format!(r#"<translate x="1"/>{b}"#)),
        sphere(&format!(r#"<transform name="to_world">{b}</transform>"#))
    ));
    let load = |text: &str| {
        let dir = dir_with(&[("s.xml", text), ("tri.obj", TRIANGLE_OBJ)]);
        Scene::load(dir.path().join("s.xml")).unwrap()
    };
    let (g, f) = (load(&grouped), load(&flat));
    assert_eq!(g.meshes.len(), 3, "the light and two triangles");
    assert_eq!(g.meshes.iter().map(|m| &m.positions).collect::<Vec<_>>(), f.meshes.iter().map(|m| &m.positions).collect::<Vec<_>>());
    assert_eq!(g.spheres.iter().map(|s| (s.center, s.radius)).collect::<Vec<_>>(), f.spheres.iter().map(|s| (s.center, s.radius)).collect::<Vec<_>>());
    assert_eq!(g.spheres[0].radius, 1.0, "scaled by its instance");
    assert_eq!(g.content_hash(), f.content_hash());
    assert_eq!(g.translation.instancing, Some(pathlab::scene::Instancing { instances: 2, groups: 1, shapes: 4 }));
    assert_eq!(f.translation.instancing, None);
    let out = pathlab().arg("check").arg({
        let dir = dir_with(&[("s.xml", &grouped), ("tri.obj", TRIANGLE_OBJ)]);
        let p = dir.path().join("s.xml");
        std::mem::forget(dir);
        p
    }).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && stdout.contains("instances: 2 of 1 shape group(s), flattened into 4 world-space shapes"), "{stdout}");

    let group = |inner: &str| format!(r#"<shape type="shapegroup" id="g">{inner}</shape>"#);
    let cases = [
        (group(r#"<shape type="sphere"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>"#), "<emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter></shape></shape>", "an emitter inside a shape group"),
        (group(r#"<shape type="shapegroup" id="h"/>"#), "<shape type=\"shapegroup\" id=\"h\"", "a shape group inside a shape group"),
        (r#"<shape type="instance"><transform name="to_world"><translate x="1"/></transform></shape>"#.to_string(), "<shape type=\"instance\">", "needs a <ref id"),
        (r#"<shape type="shapegroup"><shape type="sphere"/></shape>"#.to_string(), "<shape type=\"shapegroup\">", "needs an id"),
    ];
    for (body, at, message) in cases {
        let text = small(&format!("{body}<shape type=\"instance\"><ref id=\"g\"/></shape>").replace("<shape type=\"instance\"><ref id=\"g\"/></shape>", if body.contains("id=\"g\"") { "<shape type=\"instance\"><ref id=\"g\"/></shape>" } else { "" }));
        let (d, path) = refused(&text);
        assert!(d.message.contains(message), "expected `{message}`: {d}");
        assert_eq!((d.file.as_path(), d.line, d.column), (path.as_path(), position_of(&text, at).0, position_of(&text, at).1), "{d}");
    }
}

/// Participating media under `path`: Mitsuba's `path` integrator ignores them (checked with
/// Mitsuba 3.9.1: a glass sphere with an absorbing `homogeneous` interior renders the same image
/// as without it, to 1.2e-7), so pathlab reads a `<medium>` in a shape (inline or by `<ref>`),
/// in the sensor or named at the top level, warns that it is ignored, and renders the image
/// of the scene without it, bit for bit. Under `volpath`, where Mitsuba renders the medium,
/// it is read (tests/media.rs renders media against Mitsuba): the inline interior and the
/// exterior taken by `<ref>`.
#[test]
fn media_are_ignored_under_path_as_mitsuba_does_and_read_under_volpath() {
    let medium = r#"<medium type="homogeneous" id="fog"><rgb name="albedo" value="0"/><rgb name="sigma_t" value="0.5, 0.2, 0.4"/></medium>
    <shape type="sphere"><float name="radius" value="0.8"/><bsdf type="dielectric"/>
        <medium type="homogeneous" name="interior"><rgb name="albedo" value="0.2"/></medium>
    </shape>
    <shape type="sphere"><point name="center" x="1" y="0" z="-1"/><bsdf type="dielectric"/><ref name="exterior" id="fog"/></shape>"#;
    let plain = r#"<shape type="sphere"><float name="radius" value="0.8"/><bsdf type="dielectric"/></shape>
    <shape type="sphere"><point name="center" x="1" y="0" z="-1"/><bsdf type="dielectric"/></shape>"#;
    let with = common::load_xml(&small(medium), "media.xml").unwrap();
    let ignored: Vec<usize> = with.warnings.iter().filter(|w| w.message.contains("<medium> is ignored")).map(|w| w.line).collect();
    // Once each, where it is written (a medium taken by <ref> where it is defined).
    assert_eq!(ignored, [9, 11], "{:?}", with.warnings);
    let without = common::load_xml(&small(plain), "plain.xml").unwrap();
    assert_eq!(with.content_hash(), without.content_hash());
    let method = pathlab::method::Preset::Mis.method();
    assert_eq!(common::bits(&common::render(&with, method, 4, 1)), common::bits(&common::render(&without, method, 4, 1)));
    let volpath = small(&format!("<integrator type=\"volpath\"/>\n{medium}"));
    let scene = common::load_xml(&volpath, "volpath.xml").unwrap();
    assert_eq!(scene.media.len(), 2, "{:?}", scene.media);
    assert!(scene.warnings.iter().all(|w| !w.message.contains("<medium>")), "{:?}", scene.warnings);
    let bounded: Vec<(Option<usize>, Option<usize>)> = scene.materials.iter().map(|m| (m.interior, m.exterior)).filter(|b| *b != (None, None)).collect();
    assert_eq!(bounded.len(), 2, "{bounded:?}");
    assert!(bounded.iter().any(|(i, e)| i.is_some() && e.is_none()) && bounded.iter().any(|(i, e)| i.is_none() && e.is_some()), "{bounded:?}");
}
