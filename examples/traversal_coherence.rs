//! How much of a BVH traversal the 8 lanes of one lavapipe SIMD group share: the measurement
//! behind issue 31's question whether packet (uniform) traversal would pay.
//!
//! For the camera rays of a pinhole camera, the shadow rays of their hits towards a spherical
//! light and their cosine-weighted bounces, traversed on the CPU in the kernel's order (the
//! nearer child first; shadow rays stop at their first hit), it counts per ray the interior
//! nodes visited (passes of the kernel's node loop) and the triangles tested, and per group of
//! 8 rays (a row of 8 pixels: lavapipe's SIMD group in the kernel's 8x8 workgroup):
//! - lockstep: 8 x the group's largest count, what per-lane traversal costs on 8 lanes in step;
//! - packet: 8 x the number of distinct nodes (triangles) the group visits, what a traversal
//!   costs whose lanes visit one node together (optimistic: it ignores that a packet's order is
//!   one lane's, not each lane's own).
//! Both are printed per ray of the kind (lane-steps over rays), so a group where fewer than 8
//! lanes have such a ray (a shadow ray only where the light is above the surface) pays for its
//! idle lanes, as on lavapipe; the mean is what lanes that never wait for each other would cost.
//!
//! Usage: cargo run --release --example traversal_coherence -- SCENE.toml [LIGHT_X,Y,Z,R]
//! (the scene's camera position and direction, with the scaling scenes' 45-degree field of view, and meshes; the light defaults to the scaling scenes' sphere at
//! (1.5, 1.5, 1.5), radius 0.3, of `scripts/triangle_scaling.sh`).
use glam::Vec3;
use pathlab::accel::{Bvh, Triangle, Visit};
use std::collections::HashSet;

/// What one ray's traversal visited.
struct Visits {
    nodes: Vec<u32>,
    triangles: Vec<u32>,
    hit: Option<(f32, u32)>,
}

fn traverse(bvh: &Bvh, tris: &[Triangle], o: Vec3, d: Vec3, t_max: f32, any: bool) -> Visits {
    let (mut nodes, mut triangles) = (Vec::new(), Vec::new());
    let hit = bvh.traverse_visiting(tris, o, d, t_max, any, |step| match step {
        Visit::Node(n) => nodes.push(n),
        Visit::Triangle(t) => triangles.push(t),
    });
    Visits { nodes, triangles, hit }
}

/// A 32-bit hash to uniform [0, 1) (PCG), for the light points and bounces.
fn rnd(state: &mut u32) -> f32 {
    *state = state.wrapping_mul(747796405).wrapping_add(2891336453);
    let w = ((*state >> ((*state >> 28) + 4)) ^ *state).wrapping_mul(277803737);
    ((w >> 22) ^ w) as f32 / 4294967296.0
}

#[derive(Default)]
struct Tally {
    rays: usize,
    nodes: usize,
    nodes_lockstep: usize,
    nodes_packet: usize,
    tris: usize,
    tris_lockstep: usize,
    tris_packet: usize,
}

impl Tally {
    fn add_group(&mut self, group: &[Visits]) {
        if group.is_empty() {
            return;
        }
        self.rays += group.len();
        self.nodes += group.iter().map(|v| v.nodes.len()).sum::<usize>();
        self.tris += group.iter().map(|v| v.triangles.len()).sum::<usize>();
        self.nodes_lockstep += 8 * group.iter().map(|v| v.nodes.len()).max().unwrap();
        self.tris_lockstep += 8 * group.iter().map(|v| v.triangles.len()).max().unwrap();
        self.nodes_packet += 8 * group.iter().flat_map(|v| v.nodes.iter()).collect::<HashSet<_>>().len();
        self.tris_packet += 8 * group.iter().flat_map(|v| v.triangles.iter()).collect::<HashSet<_>>().len();
    }

    fn merged(kinds: &[&Tally]) -> Tally {
        let mut t = Tally::default();
        for k in kinds {
            t.rays += k.rays;
            t.nodes += k.nodes;
            t.nodes_lockstep += k.nodes_lockstep;
            t.nodes_packet += k.nodes_packet;
            t.tris += k.tris;
            t.tris_lockstep += k.tris_lockstep;
            t.tris_packet += k.tris_packet;
        }
        t
    }

    fn print(&self, kind: &str) {
        let r = self.rays as f64;
        println!(
            "{kind:<7} {:>7} {:>10.1} {:>14.1} {:>12.1} {:>10.1} {:>14.1} {:>12.1}",
            self.rays,
            self.nodes as f64 / r,
            self.nodes_lockstep as f64 / r,
            self.nodes_packet as f64 / r,
            self.tris as f64 / r,
            self.tris_lockstep as f64 / r,
            self.tris_packet as f64 / r
        );
    }
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let scene = pathlab::scene::Scene::load(args.get(1).ok_or_else(|| anyhow::anyhow!("usage: traversal_coherence SCENE.toml [X,Y,Z,R]"))?)?;
    let light: Vec<f32> = args.get(2).map_or(Ok(vec![1.5, 1.5, 1.5, 0.3]), |s| s.split(',').map(str::parse).collect())?;
    let (light_c, light_r) = (Vec3::new(light[0], light[1], light[2]), light[3]);
    let tris: Vec<Triangle> =
        scene.meshes.iter().flat_map(|m| (0..m.triangles.len()).map(move |t| m.vertices(t).map(|v| v.as_vec3()))).collect();
    let bvh = Bvh::build(&tris);
    let cam = &scene.camera;
    let (w, h) = (scene.render.width, scene.render.height);
    let eye = cam.position.as_vec3();
    let forward = (cam.look_at.as_vec3() - eye).normalize();
    let right = forward.cross(cam.up.as_vec3()).normalize();
    let up = right.cross(forward);
    // The scaling scenes' horizontal field of view, 45 degrees.
    let half = 22.5f32.to_radians().tan();
    let (mut camera, mut shadow, mut bounce) = (Tally::default(), Tally::default(), Tally::default());
    for y in 0..h {
        for x0 in (0..w).step_by(8) {
            let (mut cg, mut sg, mut bg) = (Vec::new(), Vec::new(), Vec::new());
            for x in x0..(x0 + 8).min(w) {
                let mut seed = (y * w + x).wrapping_mul(9781) ^ 0x9e37;
                let sx = (2.0 * (x as f32 + 0.5) / w as f32 - 1.0) * half;
                let sy = (1.0 - 2.0 * (y as f32 + 0.5) / h as f32) * half * h as f32 / w as f32;
                let d = (forward + sx * right + sy * up).normalize();
                let v = traverse(&bvh, &tris, eye, d, f32::INFINITY, false);
                if let Some((t, i)) = v.hit {
                    let p = eye + t * d;
                    let [a, b, c] = tris[i as usize];
                    let mut n = (b - a).cross(c - a).normalize();
                    if n.dot(d) > 0.0 {
                        n = -n;
                    }
                    let o = p + n * 1e-4;
                    // A uniform point on the light sphere, and the shadow ray to it.
                    let (u1, u2) = (rnd(&mut seed), rnd(&mut seed));
                    let z = 1.0 - 2.0 * u1;
                    let s = (1.0 - z * z).max(0.0).sqrt();
                    let q = light_c + light_r * Vec3::new(s * (6.2831855 * u2).cos(), s * (6.2831855 * u2).sin(), z);
                    let to = q - o;
                    if to.dot(n) > 0.0 {
                        sg.push(traverse(&bvh, &tris, o, to, 1.0 - 1e-4, true));
                    }
                    // A cosine-weighted bounce about the face normal.
                    let (u1, u2) = (rnd(&mut seed), rnd(&mut seed));
                    let (r, phi) = (u1.sqrt(), 6.2831855 * u2);
                    let (t1, t2) = n.any_orthonormal_pair();
                    let dir = (r * phi.cos()) * t1 + (r * phi.sin()) * t2 + (1.0 - u1).max(0.0).sqrt() * n;
                    bg.push(traverse(&bvh, &tris, o, dir, f32::INFINITY, false));
                }
                cg.push(v);
            }
            camera.add_group(&cg);
            shadow.add_group(&sg);
            bounce.add_group(&bg);
        }
    }
    println!("{} triangles, {} nodes, depth {}", tris.len(), bvh.nodes.len(), bvh.depth);
    println!("per ray: interior nodes visited (mean, lockstep, packet), triangles tested (mean, lockstep, packet)");
    println!("kind       rays  node mean node lockstep node packet   tri mean  tri lockstep   tri packet");
    camera.print("camera");
    shadow.print("shadow");
    bounce.print("bounce");
    Tally::merged(&[&camera, &shadow, &bounce]).print("all");
    Ok(())
}
