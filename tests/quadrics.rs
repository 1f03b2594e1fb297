//! Mitsuba's analytic `disk` and `cylinder` (src/scene/quadrics/, shaders/quadrics/), and both
//! as area lights (src/scene/emitters/{disk,cylinder}.rs, shaders/emitters/{disk,cylinder}.wgsl;
//! their sampling is chi-square tested in tests/chi2_sampling.rs).
//!
//! 1. The kernel's intersection against the host's definitions (f64): from a scene of sheared,
//!    flipped, emissive and p0/p1-placed disks and cylinders (with a sphere before them, so that
//!    object indices are offset), rays aimed at points of each (Mitsuba's `sample_position` at a
//!    grid of samples, from both sides of a disk, from outside and inside a cylinder) must hit
//!    that quadric at the point (t within 1e-4 relative), with the host's normal (within 1e-4)
//!    and uv (within 1e-4, the periodic coordinate modulo 1); rays aimed just past a disk's rim
//!    or beyond a cylinder's ends miss it. Deterministic: no false failures.
//! 2. tests/fixtures/quadrics/quadrics.xml (two disk lights, one sheared into a tilted ellipse,
//!    one turned by flip_normals; a textured elliptical disk; a two-sided textured cylinder
//!    from p0 to p1; a one-sided cylinder with normals inwards; a glowing tube, an emissive
//!    cylinder) against Mitsuba 3.9.1 loading the
//!    same file (48x48, 65536 spp in 64 passes with the variance of its mean; made by
//!    scripts/xml_fixture_reference.sh): `mis`, `best`, `nee` and `cosine` (BSDF sampling alone:
//!    the lights' one-sided emission found by rays), z-tested on blocks as tests/cornell_box.rs
//!    does (at least 99.75% of channels passing; `mis` scaled by 1.05 is rejected).
//! 3. Bad disks and cylinders are refused with the file, line and field.

use crate::common::{self, agrees_with_reference, mitsuba_fixture};

use glam::DVec3;
use pathlab::gpu::SceneFeatures;
use pathlab::method::{LightSampling, Method, Preset};
use pathlab::scene::{QuadricKind, Scene};

const PROBE_SCENE: &str = r#"
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

[materials.lamp]
emission = 2

[[spheres]]
center = [0, 40, 0]
radius = 1
material = "grey"

# Sheared: its axes neither orthogonal nor of equal length.
[[disks]]
material = "grey"
transform = { matrix = [[1.5, 0.7, 0.1, 5], [0, 0.6, 0.2, 0], [0.2, 0.1, 1, 1], [0, 0, 0, 1]] }

# A light, facing -z by flip_normals, before the other disk in the kernel's order.
[[disks]]
material = "lamp"
flip_normals = true
transform = { scale = [0.5, 0.8, 1], rotate = { axis = [1, 1, 0], angle = 40 }, translate = [-5, 0, 0] }

[[cylinders]]
material = "grey"
p0 = [0, 4, 0]
p1 = [1, 6, 0.5]
radius = 0.7

# A light, after the other cylinders in the file and first among them in the kernel's order.
[[cylinders]]
material = "lamp"
p0 = [5, -5, 0]
p1 = [5, -3.5, 1]
radius = 0.4

[[cylinders]]
material = "grey"
flip_normals = true
transform = { scale = [0.6, 0.6, 2], rotate = { axis = [0, 1, 1], angle = -30 }, translate = [0, -6, 0] }
"#;

/// A ray at a point of quadric `quadric` (its index in the scene), and what the host says the
/// kernel must find there (`None`: the ray must not hit that quadric).
struct Probe {
    origin: DVec3,
    target: DVec3,
    quadric: usize,
    hits: bool,
    what: String,
}

fn probes(scene: &Scene) -> Vec<Probe> {
    let mut probes = Vec::new();
    for (i, q) in scene.quadrics.iter().enumerate() {
        let world = |p: DVec3| q.to_world.transform_point3(p);
        for a in 0..5 {
            for b in 0..5 {
                let u = [0.1 + 0.2 * a as f64, 0.07 + 0.19 * b as f64];
                // The target in object space (Mitsuba's sample_position there).
                let p = q.to_object().transform_point3(q.sample_position(u));
                let origins = match q.kind {
                    // From above and from below the disk, slanted.
                    QuadricKind::Disk => vec![p + DVec3::new(0.1, -0.2, 0.8), p + DVec3::new(-0.15, 0.05, -0.6)],
                    // From outside, radially, and from inside towards the wall.
                    QuadricKind::Cylinder => vec![DVec3::new(1.6 * p.x, 1.6 * p.y, p.z + 0.1), DVec3::new(0.3 * p.x + 0.1, 0.3 * p.y, p.z + 0.05)],
                    _ => unreachable!("only disks and cylinders here (curves and grids: tests/linear_curves.rs, tests/bspline_curves.rs, tests/sdf_grids.rs)"),
                };
                for o in origins {
                    probes.push(Probe { origin: world(o), target: world(p), quadric: i, hits: true, what: format!("{} {i} at u {u:?} from {o}", q.kind.name()) });
                }
                // Just past the rim, or beyond an end.
                let (o, past) = match q.kind {
                    QuadricKind::Disk => {
                        let rim = DVec3::new(p.x, p.y, 0.0).normalize_or(DVec3::X) * 1.02;
                        (rim + DVec3::new(0.0, 0.0, 0.7), rim)
                    }
                    QuadricKind::Cylinder => {
                        let z = if b % 2 == 0 { -0.03 } else { 1.03 };
                        (DVec3::new(1.6 * p.x, 1.6 * p.y, z), DVec3::new(p.x, p.y, z))
                    }
                    _ => unreachable!("only disks and cylinders here"),
                };
                probes.push(Probe { origin: world(o), target: world(past), quadric: i, hits: false, what: format!("{} {i} past its edge at {past}", q.kind.name()) });
            }
        }
    }
    probes
}

#[test]
fn the_kernels_disks_and_cylinders_are_the_hosts() {
    let scene = common::scene(PROBE_SCENE);
    use QuadricKind::{Cylinder, Disk};
    assert_eq!(scene.quadrics.iter().map(|q| q.kind).collect::<Vec<_>>(), [Disk, Disk, Cylinder, Cylinder, Cylinder]);
    let mut features = SceneFeatures::of(&scene);
    assert_eq!((features.num_disks, features.num_disk_lights, features.num_cylinders, features.num_cylinder_lights), (2, 1, 3, 1));
    features.has_uvs = true;
    // The kernel's order: the disk light first, then the other disk, then the cylinder light,
    // then the other cylinders.
    let order = pathlab::gpu::features::quadric_order(&scene);
    assert_eq!(order, [1, 0, 3, 2, 4]);
    let first_quadric = (scene.spheres.len() + scene.planes.len()) as u32;
    let probes = probes(&scene);
    let rays: Vec<(DVec3, DVec3)> = probes.iter().map(|p| (p.origin, (p.target - p.origin).normalize())).collect();
    let hits = common::trace_hits(&scene, features, &rays);
    let (mut worst_t, mut worst_n, mut worst_uv) = (0.0f64, 0.0f64, 0.0f64);
    for (probe, hit) in probes.iter().zip(&hits) {
        let object = first_quadric + order.iter().position(|&k| k == probe.quadric).unwrap() as u32;
        if !probe.hits {
            assert_ne!(hit.object, object, "{}: hit at t {}", probe.what, hit.t);
            continue;
        }
        assert_eq!(hit.object, object, "{}: hit object {}", probe.what, hit.object);
        let q = &scene.quadrics[probe.quadric];
        let t = (probe.target - probe.origin).length();
        let dt = (hit.t as f64 - t).abs() / t;
        assert!(dt <= 1e-4, "{}: kernel t {}, host {t}", probe.what, hit.t);
        let n = q.normal(probe.target);
        let dn = (DVec3::from_array(hit.normal.map(f64::from)) - n).length();
        assert!(dn <= 1e-4, "{}: kernel normal {:?}, host {n}", probe.what, hit.normal);
        let uv = q.uv(probe.target);
        // The periodic coordinate (a disk's v, a cylinder's u) modulo 1.
        let periodic = if q.kind == QuadricKind::Disk { 1 } else { 0 };
        let duv = (0..2)
            .map(|c| {
                let d = (hit.uv[c] as f64 - uv[c]).abs();
                if c == periodic { d.min(1.0 - d) } else { d }
            })
            .fold(0.0, f64::max);
        assert!(duv <= 1e-4, "{}: kernel uv {:?}, host {uv:?}", probe.what, hit.uv);
        (worst_t, worst_n, worst_uv) = (worst_t.max(dt), worst_n.max(dn), worst_uv.max(duv));
    }
    eprintln!("{} probes; largest differences: t {worst_t:.1e} (relative), normal {worst_n:.1e}, uv {worst_uv:.1e}", probes.len());
}

fn plan(method: &Method) -> (u64, u32) {
    if method.lights == LightSampling::None { (4096, 4) } else { (1024, 2) }
}

#[test]
fn disks_and_cylinders_agree_with_mitsuba() {
    let reference = mitsuba_fixture("quadrics");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/quadrics/quadrics.xml"), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.lights_of(pathlab::scene::EmitterKind::Disk).len(), 2);
    assert_eq!(scene.lights_of(pathlab::scene::EmitterKind::Cylinder).len(), 1);
    // `convert` writes `[[disks]]` and `[[cylinders]]`, which load as the same scene.
    let dir = tempfile::tempdir().unwrap();
    let (toml, _) = pathlab::scene::mitsuba::to_toml(scene.path.as_path(), &defines, dir.path()).unwrap();
    assert!(toml.contains("[[disks]]") && toml.contains("[[cylinders]]"));
    std::fs::write(dir.path().join("q.toml"), &toml).unwrap();
    assert_eq!(Scene::load(dir.path().join("q.toml")).unwrap().content_hash(), scene.content_hash());
    let methods = [Preset::Mis.method(), Preset::Best.method(), Preset::Nee.method(), Preset::Cosine.method()];
    agrees_with_reference(&reference, &scene, &methods, plan, 2100, Preset::Mis.method());
}

#[test]
fn bad_disks_and_cylinders_are_refused_with_the_line_and_field() {
    let shape = |body: &str| format!("<scene version=\"3.0.0\"><sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>\n<shape type=\"rectangle\"><emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter></shape>\n{body}\n</scene>");
    for (body, expected) in [
        ("<shape type=\"cylinder\"><float name=\"radius\" value=\"0\"/></shape>", "bad.xml:3:"),
        ("<shape type=\"cylinder\"><point name=\"p1\" x=\"0\" y=\"0\" z=\"0\"/></shape>", "p0 and p1 must differ"),
        ("<shape type=\"cylinder\"><transform name=\"to_world\"><scale x=\"2\"/></transform><emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter></shape>", "an emissive cylinder must not be sheared or scaled unevenly"),
        ("<shape type=\"cylinder\"><transform name=\"to_world\"><scale x=\"-1\"/></transform></shape>", "mirrors it"),
        ("<shape type=\"disk\"><float name=\"radius\" value=\"2\"/></shape>", "bad.xml:3:"),
        ("<shape type=\"disk\"><transform name=\"to_world\"><scale z=\"0\"/></transform></shape>", "singular"),
    ] {
        let e = common::load_xml(&shape(body), "bad.xml").unwrap_err().to_string();
        assert!(e.contains(expected), "{body}: {e}");
    }
    // A cylinder scaled unevenly across its axis loads, with Mitsuba's warning.
    let scene = common::load_xml(&shape("<shape type=\"cylinder\"><transform name=\"to_world\"><scale x=\"2\"/></transform></shape>"), "uneven.xml").unwrap();
    assert!(scene.warnings.iter().any(|w| w.message.contains("unevenly")), "{:?}", scene.warnings);
}

#[test]
fn a_plane_between_the_camera_and_a_disk_light_is_tested_by_shadow_rays() {
    let scene_with = |disk: &str| {
        common::scene(&format!(
            "[camera]\nposition = [0, 0, 10]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 40\n\
             [render]\nwidth = 8\nheight = 8\nmax_depth = 2\n\
             [materials.grey]\ndiffuse = 0.5\n[materials.lamp]\nemission = 1\n\
             [[planes]]\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\nmaterial = \"grey\"\n\
             [[disks]]\nmaterial = \"lamp\"\ntransform = {disk}\n"
        ))
    };
    // Beyond the plane, on the camera's side, and on it but tilted across it.
    for (disk, occluding) in [
        ("{ translate = [0, 0, -1] }", true),
        ("{ scale = 0.5, translate = [0, 0, 1] }", false),
        ("{ rotate = { axis = [1, 0, 0], angle = 60 }, translate = [0, 0, 0.5] }", true),
    ] {
        let scene = scene_with(disk);
        assert_eq!(scene.occluding_planes().len(), occluding as usize, "{disk}");
    }
}
