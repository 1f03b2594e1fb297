//! Mitsuba's `bsplinecurve` (src/scene/quadrics/bspline_curve.rs,
//! shaders/quadrics/bspline_curve.wgsl): tubes of circles normal to cubic B-splines (their radius
//! a B-spline too), open ends, back faces culled.
//!
//! 1. The kernel's closest hit against the host's (f64: Newton from every entry into a chain of
//!    64 widened swept spheres, where the kernel has 16 and solves from the nearest two): rays
//!    from around a scene of two curves (a zig-zag of constant radius, and a
//!    curve whose radius rises from 0 and falls back) aimed at and beside each segment, rays
//!    from inside a tube and rays leaving its surface must find what the host finds: the same
//!    segment (or, at a joint, one whose hit is the same within 1e-4), t within 1e-4 relative (to
//!    at least 0.1), and at the kernel's point the host's normal within 1e-3 and uv within 1e-3
//!    (u modulo 1); a ray grazing a tube may hit in one precision alone, on the surface (at most
//!    1% of the rays). Deterministic.
//! 2. tests/fixtures/bspline_curves/bspline_curves.xml (both curves of one file with a
//!    checkerboard on their uv, as mitsuba-data's parameterization scene; the zig-zag again,
//!    moved and scaled with its radii kept, in a rough conductor) against Mitsuba 3.9.1 loading
//!    the same file (48x36, 65536 spp in 64 passes with the variance of its mean): `mis` and
//!    `best`, z-tested on blocks (at least 99.75% of channels passing; `mis` scaled by 1.05 is
//!    rejected). Fails falsely with probability below 0.01. `convert` writes
//!    `[[bspline_curves]]`, which loads as the same scene.
//! 3. The unrolled search (`BSPLINE_UNROLLED`, for scenes whose looped searches would pass
//!    llvmpipe's loop budget) finds the looped search's hits bit for bit (the rays of 1), and
//!    a scene of 37 segments at depth 64, which the looped searches would not fit, renders on
//!    a CPU adapter (where it would be refused). Deterministic.
//! 4. A curve of fewer than four points is refused at its line; an emissive curve, a normal map
//!    and flip_normals are refused.

use crate::common::{self, agrees_with_reference, mitsuba_fixture};

use glam::DVec3;
use pathlab::gpu::SceneFeatures;
use pathlab::method::Preset;
use pathlab::scene::{QuadricKind, Scene};

const FIXTURE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/bspline_curves");

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

[[bspline_curves]]
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
fn the_kernels_bspline_curves_are_the_hosts() {
    let dir = tempfile::tempdir().unwrap();
    let curves = std::fs::read_to_string(format!("{FIXTURE}/curves.txt")).unwrap();
    let scene = scene_in(dir.path(), SCENE, &curves).unwrap();
    // 7 - 3 and 6 - 3 segments.
    assert_eq!(scene.quadrics.len(), 7);
    assert!(scene.quadrics.iter().all(|q| q.kind == QuadricKind::BsplineSegment));
    let mut features = SceneFeatures::of(&scene);
    assert_eq!(features.num_bspline_segments, 7);
    features.has_uvs = true;
    let first_quadric = (scene.spheres.len() + scene.planes.len()) as u32;
    // Rays from a ring of origins around each segment, aimed at points along it and beside it
    // (grazing its surface, some missing it), from the fixture's camera, from inside the tube,
    // and leaving its surface.
    let mut rays = Vec::new();
    for q in &scene.quadrics {
        let s = q.bspline().unwrap();
        for a in 0..12 {
            let phi = a as f64 * std::f64::consts::TAU / 12.0 + 0.1;
            for v in [0.0, 0.2, 0.5, 0.9, 1.0] {
                let b = s.at(v);
                let axis = b.dc.normalize();
                let (side, up) = pathlab::scene::quadrics::angle_frame(axis);
                let dir = side * phi.cos() + up * phi.sin();
                for offset in [0.0, 0.6, 0.97, 1.03] {
                    let target = b.c + dir.cross(axis) * offset * b.r;
                    let origin = b.c + dir * 3.0 + axis * (0.3 * (a as f64 - 6.0) / 6.0);
                    rays.push((origin, (target - origin).normalize()));
                    let camera = DVec3::new(0.4, 2.2, 4.2);
                    rays.push((camera, (target - camera).normalize()));
                }
            }
        }
        let b = s.at(0.5);
        let (side, up) = pathlab::scene::quadrics::angle_frame(b.dc.normalize());
        rays.push((b.c, b.dc.normalize()));
        rays.push((b.c, side));
        // Along the axes (two zero components: the kernel's pass over the segments' bounds
        // must keep its slabs finite), through the centre line.
        for e in [DVec3::X, DVec3::Y, DVec3::Z] {
            for sign in [1.0, -1.0] {
                rays.push((b.c + e * (3.0 * sign), -e * sign));
            }
        }
        for a in 0..8 {
            for v in [0.02, 0.5, 0.98] {
                let b = s.at(v);
                let phi = a as f64 * std::f64::consts::TAU / 8.0 + 0.3;
                let p = b.c + (side * phi.cos() + up * phi.sin()).reject_from(b.dc).normalize() * b.r;
                let n = s.normal_at(p, v);
                for (tilt, turn) in [(0.2, 0.0), (0.9, 1.0), (0.5, 2.5), (0.95, 4.0)] {
                    let (t1, t2) = pathlab::scene::quadrics::angle_frame(n);
                    let dir = (n * (1.0f64 - tilt * tilt).sqrt() + (t1 * f64::cos(turn) + t2 * f64::sin(turn)) * tilt).normalize();
                    rays.push((p + n * 1e-4, dir));
                }
            }
        }
    }
    let hits = common::trace_hits(&scene, features, &rays);
    let order = pathlab::gpu::features::quadric_order(&scene);
    let segment_of = |object: u32| (object >= first_quadric && object < first_quadric + 7).then(|| order[(object - first_quadric) as usize]);
    // How far a point lies from segment q's surface (from the circle it projects on).
    let off_surface = |q: &pathlab::scene::Quadric, p: DVec3| {
        let s = q.bspline().unwrap();
        let b = s.at(s.v_of(p));
        ((p - b.c).length() - b.r).abs()
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
                assert!(off_surface(q, p) <= 1e-3 && q.normal(p).dot(d).abs() <= 0.1, "{what}: the host misses, the kernel hits segment {k} at t {}", hit.t);
                grazing += 1;
            }
            (Some((t, i)), None) => {
                let n = scene.quadrics[i].normal(o + d * t);
                assert!(n.dot(d).abs() <= 0.1, "{what}: the kernel misses (object {}), the host hits segment {i} at t {t}, normal . d {}", hit.object, n.dot(d));
                grazing += 1;
            }
            (Some((t, i)), Some(k)) => {
                found += 1;
                let dt = (hit.t as f64 - t).abs() / t.max(0.1);
                assert!(dt <= 1e-4, "{what}: kernel t {} (segment {k}), host {t} (segment {i})", hit.t);
                // At a joint two segments share the point: either may be found.
                assert!(k == i || scene.quadrics[k].intersect(o, d, 0.0, f64::INFINITY).is_some_and(|u| (u - t).abs() <= 1e-4 * t.max(0.1)), "{what}: kernel segment {k}, host {i}");
                let p = o + d * hit.t as f64;
                let q = &scene.quadrics[k];
                let n = q.normal(p);
                let dn = (DVec3::from_array(hit.normal.map(f64::from)) - n).length();
                assert!(dn <= 1e-3, "{what}: kernel normal {:?}, host {n}", hit.normal);
                let uv = q.uv(p);
                let du = (hit.uv[0] as f64 - uv[0]).abs();
                let dv = (hit.uv[1] as f64 - uv[1]).abs();
                let duv = du.min(1.0 - du).max(dv);
                // Where the tangent is within f32's rounding of +-z, the angle's frame is
                // singular (Mitsuba's (0, 1, 0) there, exact equality): f32 and f64 take
                // different sides of it (the zig-zag's turning points, seen from the side).
                let s = q.bspline().unwrap();
                let singular = s.at(s.v_of(p)).dc.normalize().z.abs() > 1.0 - 1e-6;
                assert!(duv <= 1e-3 || singular, "{what}: kernel uv {:?}, host {uv:?}", hit.uv);
                worst_uv = if singular { worst_uv } else { worst_uv.max(duv) };
                (worst_t, worst_n) = (worst_t.max(dt), worst_n.max(dn));
            }
        }
    }
    assert!(found > 1000 && missed > 100 && grazing * 100 <= rays.len(), "{found} hits, {missed} misses, {grazing} grazing");
    eprintln!("{} rays ({found} hits, {missed} misses, {grazing} grazing); largest differences: t {worst_t:.1e} (relative), normal {worst_n:.1e}, uv {worst_uv:.1e}", rays.len());
}

#[test]
fn the_unrolled_search_is_the_looped_one_and_lets_long_paths_through_many_segments_render() {
    let dir = tempfile::tempdir().unwrap();
    let curves = std::fs::read_to_string(format!("{FIXTURE}/curves.txt")).unwrap();
    let scene = scene_in(dir.path(), SCENE, &curves).unwrap();
    let features = SceneFeatures::of(&scene);
    let key = pathlab::gpu::PipelineKey::new(Preset::Mis.method(), features, scene.default_light_select());
    let unrolled = pathlab::gpu::PipelineKey { bspline_unrolled: true, ..key };
    // Rays through the curves' boxes from around them.
    let mut rays = Vec::new();
    for q in &scene.quadrics {
        let s = q.bspline().unwrap();
        for k in 0..60 {
            let target = s.at(k as f64 / 59.0).c + DVec3::new(0.0, 0.004 * (k % 7) as f64 - 0.012, 0.0);
            let origin = DVec3::new(0.4 + 0.1 * (k % 5) as f64, 2.2, 4.2 - 0.2 * (k % 3) as f64);
            rays.push((origin, (target - origin).normalize()));
        }
    }
    let (looped, unrolled) = (common::trace_hits_keyed(&scene, key, &rays), common::trace_hits_keyed(&scene, unrolled, &rays));
    assert!(looped.iter().filter(|h| h.object != u32::MAX).count() > 200);
    assert_eq!(looped, unrolled);
    // 40 points: 37 segments; at depth 64 each ray's looped searches (37 x 32 back-edges)
    // would pass llvmpipe's budget within a path.
    let many: String = (0..40).map(|i| format!("{} {} 0 0.05\n", i as f64 * 0.1 - 2.0, if i % 2 == 0 { 0.0 } else { 0.1 })).collect();
    let deep = SCENE.replace("max_depth = 2", "max_depth = 64");
    let scene = scene_in(dir.path(), &deep, &many).unwrap();
    assert_eq!(scene.quadrics.len(), 37);
    let out = dir.path().join("deep.exr");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_pathlab"))
        .args(["render", dir.path().join("scene.toml").to_str().unwrap(), "--spp", "2", "--method", "mis", "-q", "--output", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(run.status.success() && out.exists(), "{}", String::from_utf8_lossy(&run.stderr));
}

#[test]
fn bspline_curves_agree_with_mitsuba() {
    let reference = mitsuba_fixture("bspline_curves");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(format!("{FIXTURE}/bspline_curves.xml"), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.quadrics.iter().filter(|q| q.kind == QuadricKind::BsplineSegment).count(), 2 * 7, "two shapes of two curves, 4 + 3 segments");
    // `convert` writes `[[bspline_curves]]`, which load as the same scene.
    let dir = tempfile::tempdir().unwrap();
    let (toml, _) = pathlab::scene::mitsuba::to_toml(scene.path.as_path(), &defines, dir.path()).unwrap();
    assert!(toml.contains("[[bspline_curves]]"));
    std::fs::write(dir.path().join("c.toml"), &toml).unwrap();
    assert_eq!(Scene::load(dir.path().join("c.toml")).unwrap().content_hash(), scene.content_hash());
    agrees_with_reference(&reference, &scene, &[Preset::Mis.method(), Preset::Best.method()], |_| (1024, 2), 5400, Preset::Mis.method());
}

#[test]
fn bad_bspline_curves_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let curves = "0 0 0 0.1\n1 0 0 0.1\n2 1 0 0.1\n3 0 0 0.1\n\n0 2 0 0.1\n1 2 0 0.1\n2 2 0 0.1\n";
    let e = scene_in(dir.path(), SCENE, curves).unwrap_err().to_string();
    assert!(e.contains("curves.txt:6:") && e.contains("a curve of 3 control points: a B-spline curve needs at least 4"), "{e}");
    let good = "0 0 0 0.1\n1 0 0 0.1\n2 1 0 0.1\n3 0 0 0.1\n";
    let emissive = SCENE.replace("[materials.grey]\ndiffuse = 0.5", "[materials.grey]\ndiffuse = 0.5\nemission = 1");
    let e = scene_in(dir.path(), &emissive, good).unwrap_err().to_string();
    assert!(e.contains("bspline_curves[0].material") && e.contains("cannot be a light"), "{e}");
    image::RgbImage::new(2, 2).save(dir.path().join("h.png")).unwrap();
    let bumped = SCENE.replace("[materials.grey]\ndiffuse = 0.5", "[materials.grey]\ndiffuse = 0.5\nbump_map = { scale = 0.02, texture = \"bitmap\", filename = \"h.png\" }");
    let e = scene_in(dir.path(), &bumped, good).unwrap_err().to_string();
    assert!(e.contains("bspline_curves[0].material") && e.contains("normal or bump map"), "{e}");
    std::fs::write(dir.path().join("c.txt"), good).unwrap();
    for (shape, expected) in [
        ("<shape type=\"bsplinecurve\"><string name=\"filename\" value=\"c.txt\"/><boolean name=\"flip_normals\" value=\"true\"/></shape>", "flip_normals"),
        ("<shape type=\"bsplinecurve\"/>", "needs <string name=\"filename\">"),
        ("<shape type=\"bsplinecurve\"><string name=\"filename\" value=\"missing.txt\"/></shape>", "curve file"),
    ] {
        let e = common::xml_shape_error(dir.path(), shape);
        assert!(e.contains("bad.xml:3:") && e.contains(expected), "{shape}: {e}");
    }
}
