//! The uv parametrisation through the kernel's hit: each shape's texture coordinates, from
//! the scene file to `Hit.uv` in `intersect_scene` (the value `material_bsdf` receives), against
//! their definitions on the host (`Sphere::uv`, `Plane::uv`, the mesh's vertex uvs interpolated
//! at the hit's barycentrics, or the barycentrics where a mesh has none, as Mitsuba's meshes).
//!
//! A kernel built from the path tracer's own WGSL, with the scene's own buffers
//! (`SceneBuffers::contents`) and pipeline constants (`HAS_UVS` on), traces rays aimed at known
//! points of every shape: an OBJ with `vt` (its v flipped, as Mitsuba's `flip_tex_coords`), a
//! mesh without texture coordinates, Mitsuba's rectangle and cube parametrisations, a sphere
//! with rotated object axes, and a plane. Each ray must hit the shape it aims at, with uv within
//! 1e-4 of the host's (f32 against f64; the points keep away from the sphere's poles and seam,
//! where u or v are ill-conditioned). Deterministic: no false failures.

use crate::common;

use glam::DVec3;
use pathlab::gpu::SceneFeatures;
use pathlab::scene::{Scene, Sphere};

/// A quad of two triangles with texture coordinates that are not the positions' (so a swap of
/// vertices or of u and v shows), and a triangle without any.
const QUAD_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0.1 0.2\nvt 0.9 0.3\nvt 0.7 0.95\nvt 0.05 0.6\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
const BARE_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

/// A grid of 8 x 8 quads with texture coordinates that vary non-linearly over it: with it the
/// scene has more triangles than `BRUTE_FORCE_TRIANGLES`, and the kernel finds them through the
/// BVH instead of testing each in turn.
fn grid_obj() -> String {
    let n = 8;
    let mut obj = String::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
            obj += &format!("v {x} {y} 0\nvt {} {}\n", x * x, 0.3 * y + 0.2 * x * y);
        }
    }
    let v = |i: usize, j: usize| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
            obj += &format!("f {a}/{a} {b}/{b} {c}/{c}\nf {a}/{a} {c}/{c} {d}/{d}\n");
        }
    }
    obj
}

const GRID_MESH: &str = r#"
[[meshes]]
file = "grid.obj"
material = "grey"
transform = { translate = [-3, -9, 0], rotate = { axis = [1, 0, 0], angle = 20 }, scale = [2, 2, 2] }
"#;

const SCENE: &str = r#"
[camera]
position = [0, 0, 10]
look_at = [0, 0, 0]
up = [0, 1, 0]
fov_x = 60

[render]
width = 8
height = 8
max_depth = 2

[materials.grey]
diffuse = 0.5

[[meshes]]
file = "quad.obj"
material = "grey"
transform = { translate = [-6, 0, 0], scale = [2, 2, 2] }

[[meshes]]
file = "bare.obj"
material = "grey"
transform = { translate = [-6, -4, 0], scale = [2, 2, 2] }

[[rectangles]]
material = "grey"
transform = { translate = [0, -5, 0], rotate = { axis = [0, 1, 1], angle = 30 } }

[[cubes]]
material = "grey"
transform = { translate = [6, 0, 0], rotate = { axis = [1, 2, 3], angle = 40 } }

[[spheres]]
center = [0, 5, 0]
radius = 1.5
material = "grey"
# The object's x axis along the world's y, its y and z turned about it.
axes = [[0, 1, 0], [-0.8, 0, 0.6], [0.6, 0, 0.8]]

[[planes]]
point = [0, 0, -20]
normal = [0.1, 0.2, 0.9747]
material = "grey"
"#;

/// A ray aimed at a point of one shape, from outside it along the outward normal, and the uv
/// the host gives the point, with the kernel object index the hit must have (`None`: any
/// triangle).
struct Probe {
    origin: DVec3,
    direction: DVec3,
    uv: [f64; 2],
    object: Option<u32>,
    what: String,
}

fn probes(scene: &Scene) -> Vec<Probe> {
    let mut probes = Vec::new();
    // The sphere: directions spread over it, away from the poles and from the seam of u.
    let sphere = &scene.spheres[0];
    assert_ne!(sphere.axes, Sphere::WORLD_AXES);
    for i in 0..40 {
        let theta = 0.25 + (std::f64::consts::PI - 0.5) * ((i * 7 % 40) as f64 + 0.5) / 40.0;
        let phi = 0.15 + (std::f64::consts::TAU - 0.3) * (i as f64 + 0.5) / 40.0;
        // A direction in the object axes, then in the world.
        let local = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
        let n = sphere.axes[0] * local.x + sphere.axes[1] * local.y + sphere.axes[2] * local.z;
        let p = sphere.center + n * sphere.radius;
        probes.push(Probe { origin: p + n * 0.5, direction: -n, uv: sphere.uv(p), object: Some(0), what: format!("sphere at {n}") });
    }
    // The plane, seen from the camera's side.
    let plane = &scene.planes[0];
    for (x, y) in [(-3.0, 2.0), (1.5, -4.0), (7.0, 7.5), (0.0, 0.0)] {
        let p = DVec3::new(x, y, plane.point.z - (plane.normal.x * (x - plane.point.x) + plane.normal.y * (y - plane.point.y)) / plane.normal.z);
        let object = scene.spheres.len() as u32;
        probes.push(Probe { origin: p + plane.normal * 2.0, direction: -plane.normal, uv: plane.uv(p), object: Some(object), what: format!("plane at {p}") });
    }
    // Every triangle of every mesh, at a few interior barycentrics.
    for (m, mesh) in scene.meshes.iter().enumerate() {
        for t in 0..mesh.triangles.len() {
            let [p0, p1, p2] = mesh.vertices(t);
            let n = (p1 - p0).cross(p2 - p0).normalize();
            for (b1, b2) in [(0.2, 0.3), (0.6, 0.15), (0.1, 0.75), (1.0 / 3.0, 1.0 / 3.0)] {
                let b0 = 1.0 - b1 - b2;
                let p = p0 * b0 + p1 * b1 + p2 * b2;
                let uv = if mesh.uvs.is_empty() {
                    [b1, b2]
                } else {
                    let [u0, u1, u2] = mesh.triangles[t].map(|v| mesh.uvs[v as usize]);
                    [0, 1].map(|c| u0[c] * b0 + u1[c] * b1 + u2[c] * b2)
                };
                probes.push(Probe { origin: p + n * 0.25, direction: -n, uv, object: None, what: format!("mesh {m} triangle {t} at ({b1}, {b2})") });
            }
        }
    }
    probes
}

#[test]
fn every_shapes_uv_reaches_the_kernels_hit_as_the_host_defines_it() {
    // Few triangles: the kernel tests each in turn, from the uniform copy.
    let scene = probe_scene("");
    assert!(scene.num_triangles() as u32 <= pathlab::accel::BRUTE_FORCE_TRIANGLES);
    probe_uvs(&scene);
}

#[test]
fn uvs_reach_the_kernels_hit_through_the_bvh() {
    let scene = probe_scene(GRID_MESH);
    assert!(scene.num_triangles() as u32 > pathlab::accel::BRUTE_FORCE_TRIANGLES);
    probe_uvs(&scene);
}

/// The probe scene, with `extra` appended.
fn probe_scene(extra: &str) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("quad.obj"), QUAD_OBJ).unwrap();
    std::fs::write(dir.path().join("bare.obj"), BARE_OBJ).unwrap();
    std::fs::write(dir.path().join("grid.obj"), grid_obj()).unwrap();
    std::fs::write(dir.path().join("scene.toml"), format!("{SCENE}{extra}")).unwrap();
    let scene = Scene::load(dir.path().join("scene.toml")).unwrap();
    // The quad's v is flipped on loading (Mitsuba's flip_tex_coords), the bare mesh has none.
    let uv = scene.meshes[0].uvs[0];
    assert!((uv[0] - 0.1).abs() < 1e-6 && (uv[1] - 0.8).abs() < 1e-6, "{uv:?}");
    assert!(scene.meshes[1].uvs.is_empty());
    scene
}

/// Traces every probe of `scene` in the kernel and compares its hit's uv with the host's.
fn probe_uvs(scene: &Scene) {

    let probes = probes(scene);
    let mut features = SceneFeatures::of(scene);
    assert!(!features.has_uvs, "no material reads uvs: the pipelines of this scene compute none");
    features.has_uvs = true;
    let rays: Vec<(DVec3, DVec3)> = probes.iter().map(|p| (p.origin, p.direction.normalize())).collect();
    let out: Vec<[f32; 4]> = common::trace_hits(scene, features, &rays).into_iter().map(|h| [h.uv[0], h.uv[1], f32::from_bits(h.object), h.t]).collect();

    let first_triangle = (scene.spheres.len() + scene.planes.len()) as u32;
    let mut worst = 0.0f64;
    for (probe, o) in probes.iter().zip(&out) {
        let object = o[2].to_bits();
        match probe.object {
            Some(expected) => assert_eq!(object, expected, "{}: hit object {object}", probe.what),
            None => assert!(object >= first_triangle && object != u32::MAX, "{}: hit object {object}, not a triangle", probe.what),
        }
        let error = (o[0] as f64 - probe.uv[0]).abs().max((o[1] as f64 - probe.uv[1]).abs());
        assert!(error <= 1e-4, "{}: kernel uv ({}, {}), host uv {:?}", probe.what, o[0], o[1], probe.uv);
        worst = worst.max(error);
    }
    eprintln!("{} probes, largest uv difference {worst:.2e}", probes.len());
}

#[test]
fn a_mitsuba_spheres_rotation_becomes_its_object_axes() {
    let dir = tempfile::tempdir().unwrap();
    let xml = r#"<scene version="3.0.0">
        <sensor type="perspective"><float name="fov" value="40"/>
            <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
        <bsdf type="diffuse" id="grey"/>
        <shape type="sphere">
            <transform name="to_world"><scale value="2"/><rotate z="1" angle="90"/><translate x="1" y="0" z="-5"/></transform>
            <ref id="grey"/>
        </shape>
        <shape type="sphere"><point name="center" x="0" y="3" z="-5"/><ref id="grey"/></shape>
    </scene>"#;
    std::fs::write(dir.path().join("scene.xml"), xml).unwrap();
    let scene = Scene::load(dir.path().join("scene.xml")).unwrap();
    let s = &scene.spheres[0];
    assert!((s.radius - 2.0).abs() < 1e-12 && (s.center - DVec3::new(1.0, 0.0, -5.0)).length() < 1e-12);
    // Rotated by 90 degrees about z: the object's x axis is the world's y, its y the world's -x.
    for (axis, expected) in s.axes.iter().zip([DVec3::Y, -DVec3::X, DVec3::Z]) {
        assert!((*axis - expected).length() < 1e-12, "{:?}", s.axes);
    }
    // Mitsuba's u = phi / 2 pi about the object axes: the world's +y is the object's +x, u = 0;
    // the world's +x is the object's -y, u = 3/4; the equator has v = 1/2.
    let uv = s.uv(s.center + DVec3::new(-1e-9, 2.0, 0.0));
    assert!(uv[0].abs() < 1e-6 && (uv[1] - 0.5).abs() < 1e-9, "{uv:?}");
    let uv = s.uv(s.center + DVec3::new(2.0, 0.0, 0.0));
    assert!((uv[0] - 0.75).abs() < 1e-9 && (uv[1] - 0.5).abs() < 1e-9, "{uv:?}");
    // Unrotated: the world's axes, and no `axes` line in the scene hash.
    assert_eq!(scene.spheres[1].axes, Sphere::WORLD_AXES);
}

#[test]
fn sphere_axes_that_are_not_orthonormal_are_refused_with_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let bad = SCENE.replace("[0.6, 0, 0.8]]", "[0.6, 0.1, 0.8]]");
    std::fs::write(dir.path().join("quad.obj"), QUAD_OBJ).unwrap();
    std::fs::write(dir.path().join("bare.obj"), BARE_OBJ).unwrap();
    std::fs::write(dir.path().join("scene.toml"), bad).unwrap();
    let e = Scene::load(dir.path().join("scene.toml")).unwrap_err().to_string();
    assert!(e.contains("spheres[0].axes") && e.contains("orthonormal"), "{e}");
}
