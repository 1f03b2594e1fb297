//! Mitsuba's `sdfgrid` (src/scene/quadrics/sdf_grid.rs, shaders/quadrics/sdf_grid.wgsl): the
//! zero set of a signed distance grid's trilinear interpolant.
//!
//! 1. The kernel's closest hit against the host's definitions (f64): rays from around a scene of
//!    two grids of tests/fixtures/sdf_grids/ (the 24^3 torus with smooth normals, scaled, tilted
//!    and turned; the 8^3 sphere with analytic normals, scaled unevenly) aimed at points of
//!    their boxes, and rays leaving their surfaces, must find what the host finds testing every
//!    cell that holds a surface (as Mitsuba builds its primitives) with roots refined by
//!    bisection: the same grid, t within 1e-4 relative (to at least 0.1), and at the kernel's
//!    point the host's geometric normal within 1e-3 (except at most 1% of hits, each within
//!    1e-4 cells of a cell face, where the two precisions may pick the cells on either side) and
//!    the host's smooth normal within 1e-3; rays grazing a surface may hit in one precision
//!    alone, on the surface. This checks the kernel's cell walk against a search of every cell,
//!    its regula falsi against bisection, and both normals. Deterministic.
//! 2. tests/fixtures/sdf_grids/sdf_grids.xml (the torus through an instance of a shape group,
//!    the coarse sphere with analytic and with smooth normals in a rough conductor) against
//!    Mitsuba 3.9.1 loading the same file (48x36, 65536 spp in 64 passes with the variance of its
//!    mean): `mis` and `best`, z-tested on blocks (at least 99.75% of channels passing; `mis`
//!    scaled by 1.05 is rejected). Fails falsely with probability below 0.01. `convert` writes
//!    `[[sdf_grids]]`, which loads as the same scene.
//! 3. A file placed twice (an instanced group's copies) is read and uploaded once.
//! 4. Bad grids and settings are refused, naming the file and field.

use crate::common::{self, agrees_with_reference, mitsuba_fixture};

use glam::DVec3;
use pathlab::gpu::SceneFeatures;
use pathlab::method::Preset;
use pathlab::scene::{QuadricKind, Scene};

const FIXTURE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/sdf_grids");

const SCENE: &str = r#"
[camera]
position = [0, 0, 20]
look_at = [0, 0, 0]
up = [0, 1, 0]
fov_x = 40

[render]
width = 8
height = 8
max_depth = 2

[materials.grey]
diffuse = 0.5

[[spheres]]
center = [0, 40, 0]
radius = 1
material = "grey"

[[sdf_grids]]
file = "torus.vol"
material = "grey"
transform = { translate = [-1.1, -1.1, -1.1], scale = 2.2, rotate = [{ axis = [1, 0, 0], angle = 55 }, { axis = [0, 1, 0], angle = 20 }] }

[[sdf_grids]]
file = "sphere.vol"
material = "grey"
normals = "analytic"
transform = { scale = [1.2, 0.9, 1.0], translate = [1.6, 0.2, 0.3] }
"#;

fn scene_in(dir: &std::path::Path, toml: &str) -> Result<Scene, pathlab::scene::SceneError> {
    for f in ["torus.vol", "sphere.vol"] {
        std::fs::copy(format!("{FIXTURE}/{f}"), dir.join(f)).unwrap();
    }
    std::fs::write(dir.join("scene.toml"), toml).unwrap();
    Scene::load(dir.join("scene.toml"))
}

/// How far object point p of grid q lies from its nearest cell face, in cells.
fn face_distance(q: &pathlab::scene::Quadric, p: DVec3) -> f64 {
    let g = q.to_object().transform_point3(p) * q.sdf_grid().cells();
    (g - g.round()).abs().min_element()
}

#[test]
fn the_kernels_sdf_grids_are_the_hosts() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_in(dir.path(), SCENE).unwrap();
    assert_eq!(scene.quadrics.len(), 2);
    assert!(scene.quadrics.iter().all(|q| q.kind == QuadricKind::SdfGrid));
    let features = SceneFeatures::of(&scene);
    assert_eq!(features.num_sdf_grids, 2);
    assert!(features.has_shading_normals, "the torus's smooth normals are shading normals");
    let first_quadric = (scene.spheres.len() + scene.planes.len()) as u32;
    let order = pathlab::gpu::features::quadric_order(&scene);
    // Rays from six directions around each grid's box at two distances, aimed at a lattice of
    // points of the box (through the surface, past it, grazing it).
    let mut rays = Vec::new();
    for q in &scene.quadrics {
        let centre = q.to_world.transform_point3(DVec3::splat(0.5));
        for (k, dir) in [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y, DVec3::new(0.3, 0.4, 1.0), DVec3::new(-0.5, -0.2, -1.0)].into_iter().enumerate() {
            for distance in [2.5, 9.0] {
                let origin = centre + dir.normalize() * distance + DVec3::new(0.01 * k as f64, -0.02, 0.015);
                for a in 0..9 {
                    for b in 0..9 {
                        let local = DVec3::new(0.06 + 0.11 * a as f64, 0.5 + 0.13 * (b as f64 - 4.0) * (a % 3) as f64 / 2.0, 0.04 + 0.115 * b as f64);
                        let target = q.to_world.transform_point3(local.clamp(DVec3::ZERO, DVec3::ONE));
                        rays.push((origin, (target - origin).normalize()));
                    }
                }
            }
        }
    }
    // Rays leaving the surfaces the first rays found (offset along the normal, as the path
    // tracer spawns them), into the normal's hemisphere: they may meet the other side of the
    // torus, or the other grid.
    let mut leaving = Vec::new();
    for &(o, d) in rays.iter().step_by(7) {
        if let Some((t, i)) = common::nearest_quadric_hit(&scene, o, d) {
            let p = o + d * t;
            let n = scene.quadrics[i].normal(p);
            let n = if n.dot(d) < 0.0 { n } else { -n };
            let (t1, t2) = pathlab::scene::quadrics::angle_frame(n);
            for (tilt, turn) in [(0.3, 0.0), (0.9, 1.5), (0.7, 3.5)] {
                let dir = (n * (1.0f64 - tilt * tilt).sqrt() + (t1 * f64::cos(turn) + t2 * f64::sin(turn)) * tilt).normalize();
                leaving.push((p + n * 1e-4, dir));
            }
        }
    }
    rays.extend(leaving);
    let hits = common::trace_hits(&scene, features, &rays);
    let grid_of = |object: u32| (object >= first_quadric && object < first_quadric + 2).then(|| order[(object - first_quadric) as usize]);
    let (mut found, mut missed, mut grazing, mut at_faces) = (0, 0, 0, 0);
    let (mut worst_t, mut worst_n, mut worst_s) = (0.0f64, 0.0f64, 0.0f64);
    let v = |a: [f32; 3]| DVec3::from_array(a.map(f64::from));
    for (&(o, d), hit) in rays.iter().zip(&hits) {
        let what = format!("ray from {o} along {d}");
        match (common::nearest_quadric_hit(&scene, o, d), grid_of(hit.object)) {
            (None, None) => missed += 1,
            // A ray grazing a surface may meet it in one precision and not the other: the
            // kernel's point must then lie on the host's surface, the ray along it.
            (None, Some(k)) => {
                let q = &scene.quadrics[k];
                let p = o + d * hit.t as f64;
                let local = q.to_object().transform_point3(p);
                let g = q.sdf_grid();
                let off = g.lookup(local).abs() / g.gradient(local).length();
                assert!(off <= 1e-4 && q.normal(p).dot(d).abs() <= 0.1, "{what}: the host misses, the kernel hits grid {k} at t {} ({off} off its surface)", hit.t);
                grazing += 1;
            }
            (Some((t, i)), None) => {
                let n = scene.quadrics[i].normal(o + d * t);
                assert!(n.dot(d).abs() <= 0.1, "{what}: the kernel misses (object {}), the host hits grid {i} at t {t}", hit.object);
                grazing += 1;
            }
            (Some((t, i)), Some(k)) => {
                found += 1;
                assert_eq!(k, i, "{what}: kernel grid {k} at t {}, host grid {i} at {t}", hit.t);
                let dt = (hit.t as f64 - t).abs() / t.max(0.1);
                assert!(dt <= 1e-4, "{what}: kernel t {}, host {t}", hit.t);
                // The normals at the kernel's point.
                let q = &scene.quadrics[k];
                let p = o + d * hit.t as f64;
                let dn = (v(hit.normal) - q.normal(p)).length();
                if dn > 1e-3 {
                    assert!(face_distance(q, p) <= 1e-4, "{what}: kernel normal {:?}, host {} ({} cells from a face)", hit.normal, q.normal(p), face_distance(q, p));
                    at_faces += 1;
                } else {
                    worst_n = worst_n.max(dn);
                }
                let ds = (v(hit.shading_normal) - q.shading_normal(p)).length();
                assert!(ds <= 1e-3, "{what}: kernel shading normal {:?}, host {}", hit.shading_normal, q.shading_normal(p));
                (worst_t, worst_s) = (worst_t.max(dt), worst_s.max(ds));
            }
        }
    }
    assert!(found > 1000 && missed > 100 && grazing < 20 && at_faces * 100 <= found, "{found} hits, {missed} misses, {grazing} grazing, {at_faces} normals at cell faces");
    eprintln!(
        "{} rays ({found} hits, {missed} misses, {grazing} grazing, {at_faces} normals at cell faces); largest differences: t {worst_t:.1e} (relative), normal {worst_n:.1e}, smooth normal {worst_s:.1e}",
        rays.len()
    );
}

#[test]
fn sdf_grids_agree_with_mitsuba() {
    let reference = mitsuba_fixture("sdf_grids");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(format!("{FIXTURE}/sdf_grids.xml"), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let grids: Vec<_> = scene.quadrics.iter().filter_map(|q| q.grid()).collect();
    assert_eq!(grids.iter().map(|g| (g.res[0], g.smooth)).collect::<Vec<_>>(), [(24, true), (8, false), (8, true)]);
    // `convert` writes `[[sdf_grids]]`, which load as the same scene.
    let dir = tempfile::tempdir().unwrap();
    let (toml, _) = pathlab::scene::mitsuba::to_toml(scene.path.as_path(), &defines, dir.path()).unwrap();
    assert!(toml.contains("[[sdf_grids]]") && toml.contains("normals = \"analytic\""), "{toml}");
    std::fs::write(dir.path().join("c.toml"), &toml).unwrap();
    assert_eq!(Scene::load(dir.path().join("c.toml")).unwrap().content_hash(), scene.content_hash());
    agrees_with_reference(&reference, &scene, &[Preset::Mis.method(), Preset::Best.method()], |_| (1024, 2), 5400, Preset::Mis.method());
}

#[test]
fn a_file_placed_twice_is_read_and_uploaded_once() {
    let dir = tempfile::tempdir().unwrap();
    let twice = format!("{SCENE}\n[[sdf_grids]]\nfile = \"torus.vol\"\nmaterial = \"grey\"\ntransform = {{ translate = [-3, 0, 0] }}\n");
    let scene = scene_in(dir.path(), &twice).unwrap();
    let grid = |k: usize| scene.quadrics[k].grid().cloned().unwrap();
    assert!(std::sync::Arc::ptr_eq(&grid(0), &grid(2)) && !std::sync::Arc::ptr_eq(&grid(0), &grid(1)));
    let mut data = pathlab::scene::BsdfData::default();
    let records = pathlab::gpu::SceneBuffers::pack_quadrics(&scene, &mut data);
    // The torus's and the sphere's values once each, after their node counts.
    assert_eq!(data.0.len(), 3 + 24 * 24 * 24 + 3 + 8 * 8 * 8);
    assert_eq!(records[0].normal[0].to_bits(), records[2].normal[0].to_bits());
}

#[test]
fn bad_grids_and_settings_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let vol = |name: &str, res: [u32; 3], values: &[f32]| std::fs::write(dir.path().join(name), vol_bytes(res, values)).unwrap();
    vol("flat.vol", [2, 2, 2], &[1.0; 8]);
    vol("thin.vol", [2, 1, 2], &[1.0, -1.0, 1.0, -1.0]);
    vol("nan.vol", [2, 2, 2], &[1.0, -1.0, 1.0, f32::NAN, 1.0, 1.0, 1.0, 1.0]);
    let mut three = vol_bytes([2, 2, 2], &[0.5; 24]);
    three[20..24].copy_from_slice(&3i32.to_le_bytes());
    std::fs::write(dir.path().join("rgb.vol"), three).unwrap();
    let grid = |file: &str, extra: &str| SCENE.replace("file = \"sphere.vol\"", &format!("file = \"{file}\"{extra}"));
    for (toml, expected) in [
        (grid("flat.vol", ""), "no cell has corners of both signs"),
        (grid("thin.vol", ""), "at least 2 along each axis"),
        (grid("nan.vol", ""), "value (1, 1, 0) is NaN"),
        (grid("rgb.vol", ""), "3 channels (a signed distance grid has 1)"),
        (grid("missing.vol", ""), "cannot read it"),
        (SCENE.replace("normals = \"analytic\"", "normals = \"flat\""), "normals \"flat\" is not one of smooth, analytic"),
        (SCENE.replace("[materials.grey]\ndiffuse = 0.5", "[materials.grey]\ndiffuse = 0.5\nemission = 1"), "cannot be a light"),
    ] {
        let e = scene_in(dir.path(), &toml).unwrap_err().to_string();
        assert!(e.contains("sdf_grids[1]") && e.contains(expected), "{expected}: {e}");
    }
    for (shape, expected) in [
        ("<shape type=\"sdfgrid\"><string name=\"filename\" value=\"torus.vol\"/><boolean name=\"flip_normals\" value=\"true\"/></shape>", "flip_normals"),
        ("<shape type=\"sdfgrid\"/>", "needs <string name=\"filename\">"),
        ("<shape type=\"sdfgrid\"><string name=\"filename\" value=\"missing.vol\"/></shape>", "signed distance grid"),
        ("<shape type=\"sdfgrid\"><string name=\"filename\" value=\"torus.vol\"/><string name=\"normals\" value=\"flat\"/></shape>", "normals \"flat\""),
    ] {
        let e = common::xml_shape_error(dir.path(), shape);
        assert!(e.contains("bad.xml:3:") && e.contains(expected), "{shape}: {e}");
    }
}

/// The bytes of a Mitsuba `.vol` file of one channel holding `data` (x fastest), its box the
/// unit cube (`scene::vol_file`'s format).
fn vol_bytes(res: [u32; 3], data: &[f32]) -> Vec<u8> {
    let mut bytes = b"VOL\x03".to_vec();
    for v in [1i32, res[0] as i32, res[1] as i32, res[2] as i32, 1] {
        bytes.extend(v.to_le_bytes());
    }
    for v in [0.0f32, 0.0, 0.0, 1.0, 1.0, 1.0].iter().chain(data) {
        bytes.extend(v.to_le_bytes());
    }
    bytes
}
