//! Triangle lights against the exact answer: a diffuse floor lit by one emissive mesh, at
//! `max_depth` 2, has the radiance
//!     L(x) = rho / pi * Le * sum over the light's faces whose front faces x of Phi(x),
//! with Phi the projected solid angle of the face from Lambert's polygon formula,
//!     Phi = 1/2 |sum_k theta_k (gamma_k . n)|
//! (theta_k the angle an edge subtends at x, gamma_k the unit normal of the plane through x and
//! the edge). Every light is convex seen from the floor (no face hides another) and lies above
//! the floor's plane (no face crosses the horizon), so the formula is the whole answer. Each
//! pixel's exact value integrates L over the pixel (SUB x SUB sub-pixel rays, the box filter);
//! pixels whose rays hit the light, and their neighbours, are left out.
//!
//! The image mean over the remaining pixels (green channel) of every render must agree with the
//! exact mean within a Šidák-corrected z-threshold for a family-wise false-failure probability
//! of 0.01 over all renders of the file (|z| <= 3.9 or so), the standard error taken from the
//! per-pixel variances of the mean. The lights are axis-aligned, tilted about each axis, at
//! grazing angles and just above the floor; planar and non-planar; 2 to 200 faces, through the
//! brute-force path and through the BVH.

use crate::common;

use std::f64::consts::PI;

use common::*;
use glam::DVec3;
use pathlab::method::{LightSampling, LightSelect, Method, Preset, TriangleSampling};
use pathlab::scene::{Fov, Scene};
use pathlab::stats::z_threshold;

/// Sub-pixel rays per axis of the exact pixel integral (midpoint rule).
const SUB: usize = 16;

/// A light mesh in object space: vertices and counter-clockwise faces (seen from the front).
struct Lamp {
    name: &'static str,
    vertices: Vec<[f64; 3]>,
    faces: Vec<[usize; 3]>,
    /// The TOML transform of the mesh.
    transform: &'static str,
    /// Rendered with every method of `methods()` (the quads, which share their pipelines), or
    /// with `few_methods()` (the larger meshes: each triangle count compiles its own pipelines,
    /// about 1.5 s each on lavapipe).
    every_method: bool,
}

const PLACE: &str = "{ scale = 0.3, translate = [0.3, 0.8, -0.2] }";

fn quad(vertices: [[f64; 3]; 4], name: &'static str, transform: &'static str) -> Lamp {
    Lamp { name, vertices: vertices.to_vec(), faces: vec![[0, 1, 2], [0, 2, 3]], transform, every_method: true }
}

/// The quad [-1, 1]^2 in y = 0, facing down (-y).
fn down_quad(name: &'static str, transform: &'static str) -> Lamp {
    quad([[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]], name, transform)
}

/// A 10 x 10 grid of quads in y = 0 facing down, its inner vertices jittered in the plane
/// (a fixed LCG): 200 triangles of unequal areas.
fn jittered_grid() -> Lamp {
    let n = 10;
    let mut state = 12345u64;
    let mut jitter = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 33) as f64 / (1u64 << 31) as f64 - 0.5) * 0.12
    };
    let mut vertices = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let inner = i > 0 && i < n && j > 0 && j < n;
            let (dx, dz) = if inner { (jitter(), jitter()) } else { (0.0, 0.0) };
            vertices.push([-1.0 + 2.0 * i as f64 / n as f64 + dx, 0.0, -1.0 + 2.0 * j as f64 / n as f64 + dz]);
        }
    }
    let at = |i: usize, j: usize| i * (n + 1) + j;
    let mut faces = Vec::new();
    for i in 0..n {
        for j in 0..n {
            // Facing -y: (x, z) counter-clockwise seen from below.
            faces.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            faces.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    Lamp { name: "200-triangle jittered grid in y = 0 (BVH)", vertices, faces, transform: PLACE, every_method: false }
}

/// The octahedron with vertices +-e_i, its faces split into 4^k coplanar triangles, outward.
fn octahedron(k: u32, name: &'static str) -> Lamp {
    let e = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut tris: Vec<[DVec3; 3]> = Vec::new();
    for sx in [1.0, -1.0] {
        for sy in [1.0, -1.0] {
            for sz in [1.0, -1.0] {
                let a = DVec3::from(e[0]) * sx;
                let b = DVec3::from(e[1]) * sy;
                let c = DVec3::from(e[2]) * sz;
                // Outward: the winding normal along (sx, sy, sz).
                let t = if (b - a).cross(c - a).dot(DVec3::new(sx, sy, sz)) > 0.0 { [a, b, c] } else { [a, c, b] };
                tris.push(t);
            }
        }
    }
    for _ in 0..k {
        tris = tris
            .into_iter()
            .flat_map(|[a, b, c]| {
                let (ab, bc, ca) = ((a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0);
                [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
            })
            .collect();
    }
    let mut vertices = Vec::new();
    let faces = tris
        .into_iter()
        .map(|t| {
            let base = vertices.len();
            vertices.extend(t.map(|p| p.to_array()));
            [base, base + 1, base + 2]
        })
        .collect();
    Lamp { name, vertices, faces, transform: PLACE, every_method: false }
}

/// The icosahedron subdivided once and projected onto the unit sphere: 80 outward faces.
fn icosphere() -> Lamp {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<DVec3> = [[-1.0, t, 0.0], [1.0, t, 0.0], [-1.0, -t, 0.0], [1.0, -t, 0.0], [0.0, -1.0, t], [0.0, 1.0, t], [0.0, -1.0, -t], [0.0, 1.0, -t], [t, 0.0, -1.0], [t, 0.0, 1.0], [-t, 0.0, -1.0], [-t, 0.0, 1.0]]
        .iter()
        .map(|p| DVec3::from(*p).normalize())
        .collect();
    let f20: [[usize; 3]; 20] = [
        [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
        [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
    ];
    let mut mids = std::collections::HashMap::new();
    let mut mid = |a: usize, b: usize, v: &mut Vec<DVec3>| {
        *mids.entry((a.min(b), a.max(b))).or_insert_with(|| {
            v.push(((v[a] + v[b]) / 2.0).normalize());
            v.len() - 1
        })
    };
    let mut faces = Vec::new();
    for [a, b, c] in f20 {
        let (ab, bc, ca) = (mid(a, b, &mut v), mid(b, c, &mut v), mid(c, a, &mut v));
        faces.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
    }
    Lamp { name: "icosphere, 80 faces", vertices: v.iter().map(|p| p.to_array()).collect(), faces, transform: PLACE, every_method: false }
}

/// Every light of the file.
fn lamps() -> Vec<Lamp> {
    vec![
        down_quad("quad in y = 0, facing down", PLACE),
        quad([[0.0, -1.0, -1.0], [0.0, 1.0, -1.0], [0.0, 1.0, 1.0], [0.0, -1.0, 1.0]], "vertical quad in x = 0, facing +x", PLACE),
        Lamp {
            name: "trapezoid in y = 0, triangle areas 2.0 and 0.2",
            vertices: vec![[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 0.0, 1.0], [0.8, 0.0, 1.0]],
            faces: vec![[0, 1, 2], [0, 2, 3]],
            transform: PLACE,
            every_method: true,
        },
        jittered_grid(),
        quad([[-1.0, -0.5, -1.0], [1.0, 0.5, -1.0], [1.0, 0.5, 1.0], [-1.0, -0.5, 1.0]], "quad tilted by 26.6 deg, normal (2, -4, 0)", PLACE),
        quad([[-1.0, -0.5, -1.0], [1.0, 0.5, -1.0], [1.0, 0.5, 1.0], [-1.0, -0.1, 1.0]], "non-planar quad, folded away from the floor", PLACE),
        octahedron(0, "octahedron, 8 faces"),
        octahedron(2, "octahedron subdivided, 128 faces (BVH)"),
        icosphere(),
        down_quad("down quad tilted 40 deg about x", "{ scale = 0.3, rotate = { axis = [1, 0, 0], angle = 40 }, translate = [0.3, 0.8, -0.2] }"),
        down_quad("down quad tilted 35 deg about z", "{ scale = 0.3, rotate = { axis = [0, 0, 1], angle = -35 }, translate = [0.3, 0.8, -0.2] }"),
        down_quad("down quad tilted 50 deg about (1, 0, 1)", "{ scale = 0.3, rotate = { axis = [1, 0, 1], angle = 50 }, translate = [0.3, 0.8, -0.2] }"),
        quad([[0.0, -1.0, -1.0], [0.0, 1.0, -1.0], [0.0, 1.0, 1.0], [0.0, -1.0, 1.0]], "vertical quad turned 30 deg about y", "{ scale = 0.3, rotate = { axis = [0, 1, 0], angle = 30 }, translate = [0.3, 0.8, -0.2] }"),
        down_quad("down quad tilted 85 deg about x (grazing)", "{ scale = 0.3, rotate = { axis = [1, 0, 0], angle = 85 }, translate = [0.3, 0.8, -0.2] }"),
        down_quad("down quad 0.05 above the floor", "{ scale = 0.3, translate = [0.3, 0.05, -0.2] }"),
        down_quad("down quad tilted 20 deg about x, 0.12 above the floor", "{ scale = 0.3, rotate = { axis = [1, 0, 0], angle = 20 }, translate = [0.3, 0.12, -0.2] }"),
    ]
}

fn obj(lamp: &Lamp) -> String {
    let mut s = String::new();
    for v in &lamp.vertices {
        s.push_str(&format!("v {} {} {}\n", v[0], v[1], v[2]));
    }
    for f in &lamp.faces {
        s.push_str(&format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1));
    }
    s
}

/// The floor (Mitsuba's rectangle, scaled by 5, in y = 0 facing +y), reflectance 0.5, and the
/// lamp: black, emitting 10, flat-shaded (`face_normals`).
fn scene_text(lamp: &Lamp, width: u32, height: u32) -> String {
    format!(
        "[camera]\nposition = [0, 2.5, 3]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 40\n\
         [render]\nwidth = {width}\nheight = {height}\nmax_depth = 2\n\
         [materials.floor]\ndiffuse = 0.5\n[materials.lamp]\ndiffuse = 0\nemission = 10\n\
         [[rectangles]]\nmaterial = \"floor\"\ntransform = {{ scale = 5, rotate = {{ axis = [1, 0, 0], angle = -90 }} }}\n\
         [[meshes]]\nfile = \"lamp.obj\"\nmaterial = \"lamp\"\nface_normals = true\ntransform = {}\n",
        lamp.transform
    )
}

fn load(lamp: &Lamp, width: u32, height: u32) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("lamp.obj"), obj(lamp)).unwrap();
    std::fs::write(dir.path().join("scene.toml"), scene_text(lamp, width, height)).unwrap();
    Scene::load(dir.path().join("scene.toml")).unwrap_or_else(|e| panic!("{}: {e}", lamp.name))
}

/// World-space triangles of the scene's meshes, with whether each emits.
fn world_triangles(scene: &Scene) -> Vec<([DVec3; 3], bool)> {
    let mut out = Vec::new();
    for mesh in &scene.meshes {
        let emissive = scene.materials[mesh.material].is_emissive();
        assert!(!emissive || !mesh.two_sided_emission);
        for t in 0..mesh.triangles.len() {
            out.push((mesh.vertices(t), emissive));
        }
    }
    out
}

/// Distance along the ray to the triangle (Möller-Trumbore in f64), if hit.
fn hit_triangle(o: DVec3, d: DVec3, [p0, p1, p2]: [DVec3; 3]) -> Option<f64> {
    let (e1, e2) = (p1 - p0, p2 - p0);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = o - p0;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    let t = e2.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then_some(t)
}

/// Whether the ray from o along d meets the box [lo, hi] ahead of o (the slab test).
fn meets_box(o: DVec3, d: DVec3, (lo, hi): &(DVec3, DVec3)) -> bool {
    let (a, b) = ((*lo - o) / d, (*hi - o) / d);
    let (near, far) = (a.min(b).max_element(), a.max(b).min_element());
    near <= far && far >= 0.0
}

/// The light as Lambert's formula reads it: world-space vertices and front-facing-ready faces.
struct Light {
    vertices: Vec<DVec3>,
    faces: Vec<[usize; 3]>,
    /// Winding normal of each face.
    normals: Vec<DVec3>,
}

/// The light's projected solid angle at x (normal n): Lambert's formula over each face whose
/// front faces x,
///     Phi_face = 1/2 |sum over its edges (u, v) of theta(u, v) gamma(u, v) . n|,
/// theta the angle between the unit vectors u, v from x to the edge's ends and gamma the unit
/// normal of the plane through x and the edge. Every face must lie above x's tangent plane.
fn projected_solid_angle(x: DVec3, n: DVec3, light: &Light) -> f64 {
    let dirs: Vec<DVec3> = light.vertices.iter().map(|p| (*p - x).normalize()).collect();
    let mut total = 0.0;
    for (f, face) in light.faces.iter().enumerate() {
        if light.normals[f].dot(x - light.vertices[face[0]]) <= 0.0 {
            continue;
        }
        let mut sum = 0.0;
        for k in 0..3 {
            assert!(dirs[face[k]].dot(n) > 0.0, "a light face reaches below the floor's horizon");
            let (u, v) = (dirs[face[k]], dirs[face[(k + 1) % 3]]);
            let c = u.cross(v);
            let len = c.length();
            if len > 0.0 {
                sum += len.atan2(u.dot(v)) * c.dot(n) / len;
            }
        }
        total += 0.5 * sum.abs();
    }
    total
}

/// The exact image (green channel): per pixel, the box-filtered integral of L (SUB x SUB
/// midpoint sub-pixel rays), or None where a sub-pixel ray hits the light or a neighbour's does.
/// Rows are shared among the machine's cores.
fn exact_image(scene: &Scene) -> Vec<Option<f64>> {
    let (w, h) = (scene.render.width as usize, scene.render.height as usize);
    let cam = &scene.camera;
    let forward = (cam.look_at - cam.position).normalize();
    let right = forward.cross(cam.up).normalize();
    let up = right.cross(forward);
    let Some(Fov::X(deg)) = cam.fov() else { panic!("fov_x expected") };
    let half_w = (deg.to_radians() / 2.0).tan();
    let half_h = half_w * h as f64 / w as f64;
    let tris = world_triangles(scene);
    // The emissive triangles' bounding box, grown by a relative 1e-6 (a ray through a corner).
    let light_box = {
        let points = tris.iter().filter(|(_, e)| *e).flat_map(|(t, _)| *t);
        let (lo, hi) = points.fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(lo, hi), p| (lo.min(p), hi.max(p)));
        let pad = DVec3::splat(1e-6 * (hi - lo).max_element().max(1.0));
        (lo - pad, hi + pad)
    };
    let lamp = scene.meshes.iter().find(|m| scene.materials[m.material].is_emissive()).unwrap();
    let light = Light {
        vertices: lamp.positions.clone(),
        faces: lamp.triangles.iter().map(|t| t.map(|i| i as usize)).collect(),
        normals: (0..lamp.triangles.len()).map(|t| { let [a, b, c] = lamp.vertices(t); (b - a).cross(c - a) }).collect(),
    };
    let floor = &scene.materials[scene.meshes.iter().find(|m| !scene.materials[m.material].is_emissive()).unwrap().material];
    let (rho, le) = (floor.bsdf.as_phong().unwrap().diffuse.y, scene.materials[lamp.material].emission.y);
    // Per row: each pixel's integral, and whether a sub-pixel ray saw the light.
    let row = |py: usize| -> Vec<(f64, bool)> {
        (0..w)
            .map(|px| {
                let (mut sum, mut sees_light) = (0.0, false);
                for sy in 0..SUB {
                    for sx in 0..SUB {
                        let ndc_x = 2.0 * (px as f64 + (sx as f64 + 0.5) / SUB as f64) / w as f64 - 1.0;
                        let ndc_y = 1.0 - 2.0 * (py as f64 + (sy as f64 + 0.5) / SUB as f64) / h as f64;
                        let d = (forward + ndc_x * half_w * right + ndc_y * half_h * up).normalize();
                        // The light's triangles only where the ray meets their bounding box.
                        let near_light = meets_box(cam.position, d, &light_box);
                        let nearest = tris
                            .iter()
                            .filter(|(_, e)| !e || near_light)
                            .filter_map(|(t, e)| hit_triangle(cam.position, d, *t).map(|dist| (dist, *t, *e)))
                            .min_by(|a, b| a.0.total_cmp(&b.0));
                        let Some((dist, tri, emissive)) = nearest else { continue };
                        if emissive {
                            sees_light = true;
                            continue;
                        }
                        let x = cam.position + d * dist;
                        let mut n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize();
                        if n.dot(d) > 0.0 {
                            n = -n;
                        }
                        sum += rho / PI * le * projected_solid_angle(x, n, &light);
                    }
                }
                (sum / (SUB * SUB) as f64, sees_light)
            })
            .collect()
    };
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let rows: Vec<Vec<(f64, bool)>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads).map(|k| s.spawn(move || (k..h).step_by(threads).map(|py| (py, row(py))).collect::<Vec<_>>())).collect();
        let mut rows = vec![Vec::new(); h];
        for handle in handles {
            for (py, r) in handle.join().unwrap() {
                rows[py] = r;
            }
        }
        rows
    });
    let sees_light = |x: i64, y: i64| x >= 0 && y >= 0 && x < w as i64 && y < h as i64 && rows[y as usize][x as usize].1;
    (0..w * h)
        .map(|i| {
            let (px, py) = ((i % w) as i64, (i / w) as i64);
            let near_light = (-1..=1).any(|dy| (-1..=1).any(|dx| sees_light(px + dx, py + dy)));
            (!near_light).then_some(rows[i / w][i % w].0)
        })
        .collect()
}

/// Checks that no front face of the light can hide another from a point in front of both: every
/// vertex of the light lies on or behind the plane of every face.
fn assert_convex(lamp: &Lamp, scene: &Scene) {
    let lights: Vec<[DVec3; 3]> = world_triangles(scene).into_iter().filter(|t| t.1).map(|t| t.0).collect();
    for l in &lights {
        let n = (l[1] - l[0]).cross(l[2] - l[0]).normalize();
        for m in &lights {
            for p in m {
                assert!((*p - l[0]).dot(n) <= 1e-9, "{}: the light is not convex seen from its front", lamp.name);
            }
        }
    }
}

/// plain, cosine, nee, mis and best; those that sample lights with every light selection and
/// both triangle samplings.
fn methods() -> Vec<Method> {
    triangle_light_methods_of(&[Preset::Plain, Preset::Cosine, Preset::Nee, Preset::Mis, Preset::Best])
}

/// plain, cosine, nee, mis and best, with each light selection and triangle sampling once.
fn few_methods() -> Vec<Method> {
    let with = |p: Preset, select, triangles| Method { select: Some(select), triangles, ..p.method() };
    vec![
        Preset::Plain.method(),
        Preset::Cosine.method(),
        with(Preset::Nee, LightSelect::All, TriangleSampling::Area),
        with(Preset::Nee, LightSelect::Uniform, TriangleSampling::SolidAngle),
        with(Preset::Mis, LightSelect::Power, TriangleSampling::Area),
        with(Preset::Best, LightSelect::All, TriangleSampling::SolidAngle),
    ]
}

/// Samples per pixel of a method: the ones without light sampling are far noisier.
fn spp(method: &Method) -> u64 {
    if method.lights == LightSampling::None { 64 } else { 16 }
}

#[test]
fn triangle_lights_give_lamberts_exact_value_for_every_method_selection_and_sampling() {
    let lamps = lamps();
    let (all, few) = (methods(), few_methods());
    let methods_of = |lamp: &Lamp| if lamp.every_method { &all } else { &few };
    let threshold = z_threshold(0.01, lamps.iter().map(|l| methods_of(l).len()).sum());
    let mut report = Vec::new();
    let mut failed = Vec::new();
    let mut seed = 1000u32;
    for lamp in &lamps {
        let scene = load(lamp, 64, 48);
        assert_eq!(scene.num_triangles(), 2 + lamp.faces.len(), "{}", lamp.name);
        assert_convex(lamp, &scene);
        let exact = exact_image(&scene);
        let pixels: Vec<usize> = (0..exact.len()).filter(|&i| exact[i].is_some()).collect();
        assert!(pixels.len() > exact.len() / 2, "{}: too few floor pixels", lamp.name);
        let exact_mean = pixels.iter().map(|&i| exact[i].unwrap()).sum::<f64>() / pixels.len() as f64;
        report.push(format!("{} (exact mean {exact_mean:.6} over {} pixels):", lamp.name, pixels.len()));
        for method in methods_of(lamp) {
            seed += 1;
            let film = render(&scene, *method, spp(method), seed);
            let n = pixels.len() as f64;
            let mean = pixels.iter().map(|&i| film.mean[i][1] as f64).sum::<f64>() / n;
            let err = pixels.iter().map(|&i| film.variance[i][1] as f64).sum::<f64>().sqrt() / n;
            let z = (mean - exact_mean) / err;
            let line = format!(
                "    {:<34} {:+.3}% +- {:.3}%  z {z:+.2}",
                method.name(),
                100.0 * (mean / exact_mean - 1.0),
                100.0 * err / exact_mean
            );
            report.push(line.clone());
            if !(z.abs() <= threshold) {
                failed.push(format!("{}: {}", lamp.name, line.trim()));
            }
        }
    }
    println!("{}\n|z| <= {threshold:.2}", report.join("\n"));
    assert!(failed.is_empty(), "disagree with Lambert's formula (|z| > {threshold:.2}):\n{}", failed.join("\n"));
}

