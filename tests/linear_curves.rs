//! Mitsuba's `linearcurve` (src/scene/quadrics/linear_curve.rs, shaders/quadrics/linear_curve.wgsl):
//! tubes along polylines, each segment the sphere swept along it (a cone tangent to its two end
//! spheres, and the spheres), back faces culled.
//!
//! 1. The kernel's closest hit against the host's definitions (f64): rays from around a scene of
//!    two curves (a zig-zag of constant radius, whose capsules overlap at the joints, and a curve
//!    whose radius varies along it) aimed at and beside each segment must find what the host's
//!    nearest entry over every segment finds: the same segment (or one whose entry point is the
//!    same, within 1e-4, at a joint), t within 1e-4 relative (to at least 0.1), and at the kernel's point the
//!    host's normal within 1e-4 and uv within 1e-4 (u modulo 1); rays grazing a tube may hit in
//!    one precision alone, on the surface; rays from inside a tube see nothing of it.
//!    Deterministic.
//! 2. tests/fixtures/linear_curves/linear_curves.xml (both curves of one file with a checkerboard
//!    on their uv, as mitsuba-data's parameterization scene; the zig-zag again, moved and scaled
//!    with its radii kept, in a rough conductor) against Mitsuba 3.9.1 loading the same file
//!    (48x36, 65536 spp in 64 passes with the variance of its mean): `mis` and `best`, z-tested on
//!    blocks (at least 99.75% of channels passing; `mis` scaled by 1.05 is rejected). Fails
//!    falsely with probability below 0.01. `convert` writes `[[linear_curves]]`, which loads as
//!    the same scene.
//! 3. Bad curve files are refused at their line; an emissive curve and flip_normals are refused.

use crate::common::{self, agrees_with_reference, mitsuba_fixture};

use glam::DVec3;
use pathlab::gpu::SceneFeatures;
use pathlab::method::Preset;
use pathlab::scene::{QuadricKind, Scene};

const CURVES: &str = "-1.0 0.0 -1.0 0.1\n-0.6667 0.0 1.0 0.1\n-0.3333 0.0 -1.0 0.1\n0.0 0.0 1.0 0.1\n0.3333 0.0 -1.0 0.1\n\n\
                      -1.0 0.6 -0.8 0.25\n-0.2 0.9 0.0 0.08\n0.6 0.6 0.7 0.18\n1.1 0.8 0.9 0.02\n";

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

[[linear_curves]]
file = "curves.txt"
material = "grey"
transform = { rotate = { axis = [0, 1, 0], angle = 20 }, translate = [0, 0.25, 0] }
"#;

fn scene_in(dir: &std::path::Path, toml: &str, curves: &str) -> Result<Scene, pathlab::scene::SceneError> {
    std::fs::write(dir.join("curves.txt"), curves).unwrap();
    std::fs::write(dir.join("scene.toml"), toml).unwrap();
    Scene::load(dir.join("scene.toml"))
}

#[test]
fn the_kernels_curves_are_the_hosts() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_in(dir.path(), SCENE, CURVES).unwrap();
    assert_eq!(scene.quadrics.len(), 7);
    assert!(scene.quadrics.iter().all(|q| q.kind == QuadricKind::CurveSegment));
    let mut features = SceneFeatures::of(&scene);
    assert_eq!(features.num_curve_segments, 7);
    features.has_uvs = true;
    let first_quadric = (scene.spheres.len() + scene.planes.len()) as u32;
    // Rays from a ring of origins around each segment, aimed at points along it and slightly
    // beside it (grazing the surface, some missing it), and from inside a tube along it.
    let mut rays = Vec::new();
    for q in &scene.quadrics {
        let c = q.curve().unwrap();
        let axis = c.axis();
        let (side, up) = pathlab::scene::quadrics::angle_frame(axis);
        for a in 0..12 {
            let phi = a as f64 * std::f64::consts::TAU / 12.0 + 0.1;
            let dir = side * phi.cos() + up * phi.sin();
            for s in [0.0, 0.2, 0.5, 0.9, 1.0] {
                for offset in [0.0, 0.6, 0.97, 1.03] {
                    let centre = c.p0.lerp(c.p1, s);
                    let r = c.r0 + (c.r1 - c.r0) * s;
                    let target = centre + dir.cross(axis) * offset * r;
                    let origin = centre + dir * 3.0 + axis * (0.3 * (a as f64 - 6.0) / 6.0);
                    rays.push((origin, (target - origin).normalize()));
                    // From the fixture's camera, 5 units away.
                    let camera = DVec3::new(0.4, 2.2, 4.2);
                    rays.push((camera, (target - camera).normalize()));
                }
            }
        }
        // From inside the tube, along it and across it: back faces only.
        let mid = c.p0.lerp(c.p1, 0.5);
        rays.push((mid, axis));
        rays.push((mid, side));
        // Leaving its surface (as rays the path tracer spawns there, offset along the normal),
        // near the joints too, into the hemisphere of the normal: they may meet other segments.
        for a in 0..8 {
            for s in [0.02, 0.5, 0.98] {
                let phi = a as f64 * std::f64::consts::TAU / 8.0 + 0.3;
                let n = side * phi.cos() + up * phi.sin();
                let p = c.p0.lerp(c.p1, s) + n * (c.r0 + (c.r1 - c.r0) * s);
                let n = q.normal(p);
                for (tilt, turn) in [(0.2, 0.0), (0.9, 1.0), (0.5, 2.5), (0.95, 4.0)] {
                    let (t1, t2) = pathlab::scene::quadrics::angle_frame(n);
                    let dir = (n * (1.0 - tilt * tilt as f64).sqrt() + (t1 * f64::cos(turn) + t2 * f64::sin(turn)) * tilt).normalize();
                    rays.push((p + n * 1e-4, dir));
                }
            }
        }
    }
    let hits = common::trace_hits(&scene, features, &rays);
    let order = pathlab::gpu::features::quadric_order(&scene);
    let segment_of = |object: u32| (object >= first_quadric && object < first_quadric + 7).then(|| order[(object - first_quadric) as usize]);
    // How far a point lies from segment q's surface (its contact sphere's).
    let off_surface = |q: &pathlab::scene::Quadric, p: DVec3| {
        let c = q.curve().unwrap();
        let v = c.v_local(p);
        ((p - c.p0.lerp(c.p1, v)).length() - (c.r0 + (c.r1 - c.r0) * v)).abs()
    };
    let (mut found, mut missed, mut grazing) = (0, 0, 0);
    let (mut worst_t, mut worst_n, mut worst_uv) = (0.0f64, 0.0f64, 0.0f64);
    for (&(o, d), hit) in rays.iter().zip(&hits) {
        let what = format!("ray from {o} along {d}");
        match (common::nearest_quadric_hit(&scene, o, d), segment_of(hit.object)) {
            (None, None) => missed += 1,
            // A ray grazing a tube may meet it in one precision and not the other: the kernel's
            // point must then lie on the host's surface, the ray along it.
            (None, Some(k)) => {
                let q = &scene.quadrics[k];
                let p = o + d * hit.t as f64;
                assert!(off_surface(q, p) <= 1e-4 && q.normal(p).dot(d).abs() <= 0.05, "{what}: the host misses, the kernel hits segment {k} at t {}", hit.t);
                grazing += 1;
            }
            (Some((t, i)), None) => {
                let n = scene.quadrics[i].normal(o + d * t);
                assert!(n.dot(d).abs() <= 0.05, "{what}: the kernel misses (object {}), the host hits segment {i} at t {t}", hit.object);
                grazing += 1;
            }
            (Some((t, i)), Some(k)) => {
                found += 1;
                let q = &scene.quadrics[i];
                let p = o + d * t;
                // Relative to the distance, or to 0.1 for rays from a surface (f32's error is of
                // the coordinates' size).
                let dt = (hit.t as f64 - t).abs() / t.max(0.1);
                assert!(dt <= 1e-4, "{what}: kernel t {} (segment {k}), host {t} (segment {i})", hit.t);
                // At a joint two segments share the entry point: either may be found.
                let same = k == i;
                assert!(same || scene.quadrics[k].intersect(o, d, 0.0, f64::INFINITY).is_some_and(|u| (u - t).abs() <= 1e-4 * t.max(0.1)), "{what}: kernel segment {k}, host {i}");
                assert!(q.normal(p).dot(d) < 0.0, "{what}: the host's entry faces the ray");
                // The normal and uv at the kernel's point (an f32 point's error, divided by a
                // radius of 0.02 to 0.25, would dominate the comparison at the host's).
                let p = o + d * hit.t as f64;
                let q = &scene.quadrics[k];
                let n = q.normal(p);
                let dn = (DVec3::from_array(hit.normal.map(f64::from)) - n).length();
                assert!(dn <= 1e-4, "{what}: kernel normal {:?}, host {n}", hit.normal);
                let uv = q.uv(p);
                let du = (hit.uv[0] as f64 - uv[0]).abs();
                let dv = (hit.uv[1] as f64 - uv[1]).abs();
                let duv = du.min(1.0 - du).max(dv);
                assert!(duv <= 1e-4, "{what}: kernel uv {:?}, host {uv:?}", hit.uv);
                (worst_t, worst_n, worst_uv) = (worst_t.max(dt), worst_n.max(dn), worst_uv.max(duv));
            }
        }
    }
    assert!(found > 1000 && missed > 100 && grazing < 40, "{found} hits, {missed} misses, {grazing} grazing");
    eprintln!("{} rays ({found} hits, {missed} misses, {grazing} grazing); largest differences: t {worst_t:.1e} (relative), normal {worst_n:.1e}, uv {worst_uv:.1e}", rays.len());
}

#[test]
fn linear_curves_agree_with_mitsuba() {
    let reference = mitsuba_fixture("linear_curves");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/linear_curves/linear_curves.xml"), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.quadrics.iter().filter(|q| q.kind == QuadricKind::CurveSegment).count(), 2 * 9, "two shapes of two curves, 6 + 3 segments");
    // `convert` writes `[[linear_curves]]`, which load as the same scene.
    let dir = tempfile::tempdir().unwrap();
    let (toml, _) = pathlab::scene::mitsuba::to_toml(scene.path.as_path(), &defines, dir.path()).unwrap();
    assert!(toml.contains("[[linear_curves]]"));
    std::fs::write(dir.path().join("c.toml"), &toml).unwrap();
    assert_eq!(Scene::load(dir.path().join("c.toml")).unwrap().content_hash(), scene.content_hash());
    agrees_with_reference(&reference, &scene, &[Preset::Mis.method(), Preset::Best.method()], |_| (1024, 2), 5400, Preset::Mis.method());
}

#[test]
fn bad_curves_are_refused_at_their_line() {
    let dir = tempfile::tempdir().unwrap();
    for (curves, line, expected) in [
        ("0 0 0 0.1\n1 0 0\n", 2, "x y z radius"),
        ("0 0 0 0.1\n1 0 0 0.1\n\n2 2 2 0.1\n", 4, "a curve of one control point: a linear curve needs at least 2"),
        ("0 0 0 0.1\n1 0 nan 0.1\n", 2, "finite"),
        ("0 0 0 0.1\n1 0 0 -0.1\n", 2, "negative"),
        ("0 0 0 1\n0.5 0 0 0.1\n", 0, "end sphere inside the other"),
    ] {
        let e = scene_in(dir.path(), SCENE, curves).unwrap_err().to_string();
        let at = if line > 0 { format!("curves.txt:{line}:") } else { "linear_curves[0].file".to_string() };
        assert!(e.contains(&at) && e.contains(expected), "{curves:?}: {e}");
    }
    let emissive = SCENE.replace("[materials.grey]\ndiffuse = 0.5", "[materials.grey]\ndiffuse = 0.5\nemission = 1");
    let e = scene_in(dir.path(), &emissive, CURVES).unwrap_err().to_string();
    assert!(e.contains("cannot be a light"), "{e}");
    std::fs::write(dir.path().join("c.txt"), CURVES).unwrap();
    for (shape, expected) in [
        ("<shape type=\"linearcurve\"><string name=\"filename\" value=\"c.txt\"/><boolean name=\"flip_normals\" value=\"true\"/></shape>", "flip_normals"),
        ("<shape type=\"linearcurve\"/>", "needs <string name=\"filename\">"),
        ("<shape type=\"linearcurve\"><string name=\"filename\" value=\"missing.txt\"/></shape>", "curve file"),
    ] {
        let e = common::xml_shape_error(dir.path(), shape);
        assert!(e.contains("bad.xml:3:") && e.contains(expected), "{shape}: {e}");
    }
}
