//! The BVH (CPU side, `pathlab::accel`) against brute force: the closest hit and the any-hit of
//! every ray agree with testing every triangle, on random soups and on the nasty cases:
//! coplanar, axis-aligned, huge and tiny triangles, a mesh far from the origin; and rays aimed
//! exactly at the shared edges and vertices of a closed mesh, from inside, all hit (watertight:
//! not one escapes). Deterministic (fixed seeds); exact agreement is required (the BVH runs the
//! same triangle test, so its box culling must never drop a hit).

use glam::Vec3;

use pathlab::accel::{Bvh, ShearedRay, Triangle};

/// SplitMix64.
struct Rng(u64);

impl Rng {
    fn u(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.u()
    }
    fn vec(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
    fn dir(&mut self) -> Vec3 {
        loop {
            let v = self.vec(-1.0, 1.0);
            if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
                return v;
            }
        }
    }
}

fn brute(tris: &[Triangle], o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
    let ray = ShearedRay::new(o, d);
    tris.iter().filter_map(|[a, b, c]| ray.hit(*a, *b, *c, t_max).map(|h| h.0)).fold(None, |best, t| Some(best.map_or(t, |b: f32| b.min(t))))
}

/// Every ray's closest and any hit through the BVH equal brute force's; returns the hits.
fn agree(name: &str, tris: &[Triangle], rays: &[(Vec3, Vec3)]) -> usize {
    let bvh = Bvh::build(tris);
    assert!(bvh.depth < pathlab::accel::bvh::MAX_DEPTH, "{name}: depth {}", bvh.depth);
    let mut hits = 0;
    for (k, &(o, d)) in rays.iter().enumerate() {
        let expected = brute(tris, o, d, f32::INFINITY);
        let got = bvh.closest(tris, o, d, f32::INFINITY).map(|h| h.0);
        assert_eq!(got, expected, "{name}: ray {k} ({o:?} + t {d:?}): closest");
        let shadow_max = expected.map_or(10.0, |t| t * 1.5);
        assert_eq!(bvh.any(tris, o, d, shadow_max), brute(tris, o, d, shadow_max).is_some(), "{name}: ray {k}: any");
        hits += expected.is_some() as usize;
    }
    hits
}

fn soup(rng: &mut Rng, n: usize, size: (f32, f32), spread: f32, offset: Vec3) -> Vec<Triangle> {
    (0..n)
        .map(|_| {
            let c = offset + rng.vec(-spread, spread);
            let s = rng.range(size.0, size.1);
            [c + rng.vec(-s, s), c + rng.vec(-s, s), c + rng.vec(-s, s)]
        })
        .collect()
}

fn random_rays(rng: &mut Rng, n: usize, around: Vec3, spread: f32) -> Vec<(Vec3, Vec3)> {
    (0..n).map(|_| (around + rng.vec(-spread, spread), rng.dir())).collect()
}

#[test]
fn closest_and_any_hit_agree_with_brute_force_on_soups_and_nasty_cases() {
    let mut rng = Rng(7);
    // Random soups of small and of mixed sizes.
    let tris = soup(&mut rng, 2000, (0.01, 0.1), 1.0, Vec3::ZERO);
    let rays = random_rays(&mut rng, 40_000, Vec3::ZERO, 1.5);
    let hits = agree("soup", &tris, &rays);
    // Not vacuous: 4468 of the 40,000 rays hit (measured).
    assert!(hits > 2_000, "soup: only {hits} hits");
    let mut mixed = soup(&mut rng, 500, (1e-4, 1e-3), 1.0, Vec3::ZERO);
    mixed.extend(soup(&mut rng, 20, (1e3, 1e4), 1.0, Vec3::ZERO));
    mixed.extend(soup(&mut rng, 500, (0.05, 0.3), 1.0, Vec3::ZERO));
    agree("huge and tiny", &mixed, &random_rays(&mut rng, 20_000, Vec3::ZERO, 1.0));
    // Coplanar, axis-aligned: a grid of quads in z = 0, rays straight down and grazing.
    let mut grid = Vec::new();
    for i in 0..32 {
        for j in 0..32 {
            let (x, y) = (i as f32 / 8.0 - 2.0, j as f32 / 8.0 - 2.0);
            let (p, q, r, s) = (Vec3::new(x, y, 0.0), Vec3::new(x + 0.125, y, 0.0), Vec3::new(x, y + 0.125, 0.0), Vec3::new(x + 0.125, y + 0.125, 0.0));
            grid.push([p, q, s]);
            grid.push([p, s, r]);
        }
    }
    let mut rays: Vec<(Vec3, Vec3)> = (0..10_000).map(|_| (Vec3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), 1.0), -Vec3::Z)).collect();
    // Aimed at the grid's vertices and edges, exactly.
    for i in 0..33 {
        for j in 0..33 {
            let p = Vec3::new(i as f32 / 8.0 - 2.0, j as f32 / 8.0 - 2.0, 1.0);
            rays.push((p, -Vec3::Z));
            rays.push((p + Vec3::new(0.0625, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0)));
        }
    }
    rays.extend((0..5_000).map(|_| (Vec3::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), 0.0), Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0))));
    rays.extend(random_rays(&mut rng, 5_000, Vec3::new(0.0, 0.0, 0.5), 2.0));
    agree("coplanar grid", &grid, &rays);
    // A soup far from the origin (f32 spacing there is ~1e-3).
    let far = Vec3::new(1.0e4, -2.0e4, 3.0e4);
    let tris = soup(&mut rng, 2000, (0.5, 5.0), 100.0, far);
    agree("far from the origin", &tris, &random_rays(&mut rng, 20_000, far, 150.0));
}

/// An icosphere: a closed mesh whose triangles share every edge with a neighbour.
fn icosphere(subdivisions: u32) -> Vec<Triangle> {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let v: Vec<Vec3> = [
        (-1.0, t, 0.0), (1.0, t, 0.0), (-1.0, -t, 0.0), (1.0, -t, 0.0), (0.0, -1.0, t), (0.0, 1.0, t),
        (0.0, -1.0, -t), (0.0, 1.0, -t), (t, 0.0, -1.0), (t, 0.0, 1.0), (-t, 0.0, -1.0), (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let faces = [
        (0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
        (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1),
    ];
    let mut tris: Vec<Triangle> = faces.iter().map(|&(a, b, c)| [v[a], v[b], v[c]]).collect();
    for _ in 0..subdivisions {
        // Midpoints are computed once per edge from the same two vertices, so neighbours share
        // them bit for bit.
        let mid = |a: Vec3, b: Vec3| {
            let (p, q) = if a.to_array() < b.to_array() { (a, b) } else { (b, a) };
            ((p + q) * 0.5).normalize()
        };
        tris = tris
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    tris
}

#[test]
fn rays_through_shared_edges_and_vertices_of_a_closed_mesh_never_escape() {
    let mesh = icosphere(3);
    let bvh = Bvh::build(&mesh);
    let mut rng = Rng(11);
    let mut aimed = 0;
    for [a, b, c] in &mesh {
        // At the vertices and at points of the edges (the midpoint, and random points), from
        // the centre and from random points inside.
        let mut targets = vec![*a, *b, *c, (*a + *b) * 0.5, (*b + *c) * 0.5, (*c + *a) * 0.5];
        for _ in 0..2 {
            let s = rng.u();
            targets.push(*a + (*b - *a) * s);
        }
        for target in targets {
            for origin in [Vec3::ZERO, rng.vec(-0.3, 0.3)] {
                let d = target - origin;
                aimed += 1;
                assert!(bvh.closest(&mesh, origin, d, f32::INFINITY).is_some(), "a ray from {origin:?} to {target:?} escaped");
                assert!(bvh.any(&mesh, origin, d, 2.0), "shadow ray from {origin:?} to {target:?} escaped");
            }
        }
    }
    assert!(aimed > 10_000);
}

// ----- the kernel's traversal (bvh.wgsl) on lavapipe --------------------------------------------

use crate::common;

const BVH_KERNEL: &str = r#"
struct TestRay { o: vec4f, d: vec4f }
@group(0) @binding(0) var<storage, read> test_rays: array<TestRay>;
@group(0) @binding(1) var<storage, read_write> test_out: array<vec4f>;

@compute @workgroup_size(64)
fn bvh_main(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x;
    if (i >= arrayLength(&test_rays)) {
        return;
    }
    let r = test_rays[i];
    let closest = bvh_traverse(r.o.xyz, r.d.xyz, r.o.w, false);
    let any = bvh_traverse(r.o.xyz, r.d.xyz, r.d.w, true);
    test_out[i] = vec4f(select(-1.0, closest.t, closest.index != INVALID), bitcast<f32>(closest.index),
                        select(0.0, 1.0, any.index != INVALID), select(0.0, 1.0, traversal_exhausted));
}

// Every triangle tested in turn with the kernel's own arithmetic: the closest hit below the
// ray's closest t_max, as the traversal would find it.
@compute @workgroup_size(64)
fn brute_main(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x;
    if (i >= arrayLength(&test_rays)) {
        return;
    }
    let r = test_rays[i];
    let ray = sheared_ray(r.o.xyz, r.d.xyz);
    var best = TriangleHit(r.o.w, INVALID, vec2f(0.0));
    for (var k = 0u; k < NUM_TRIANGLES; k++) {
        let tri = triangle_record(k);
        var bary: vec2f;
        let t = intersect_triangle(ray, tri.p0, tri.p1, tri.p2, best.t, &bary);
        if (t > 0.0) {
            best = TriangleHit(t, k, bary);
        }
    }
    test_out[i] = vec4f(select(-1.0, best.t, best.index != INVALID), bitcast<f32>(best.index), 0.0, 0.0);
}

// The small scenes' unrolled tests (generated: `triangles_brute_force`, on shared vertices),
// for a module assembled with them unrolled to the scene's triangle count: the closest hit, then
// a shadow ray's (only the triangles SMALL_SHADOW_TESTS_<k> keeps).
@compute @workgroup_size(64)
fn small_main(@builtin(global_invocation_id) gid: vec3u) {
    load_small_triangles();
    let i = gid.x;
    if (i >= arrayLength(&test_rays)) {
        return;
    }
    let r = test_rays[i];
    let best = triangles_brute_force(r.o.xyz, r.d.xyz, r.o.w, false);
    test_out[2u * i] = vec4f(select(-1.0, best.t, best.index != INVALID), bitcast<f32>(best.index), best.bary);
    let shadow = triangles_brute_force(r.o.xyz, r.d.xyz, r.o.w, true);
    test_out[2u * i + 1u] = vec4f(select(-1.0, shadow.t, shadow.index != INVALID), bitcast<f32>(shadow.index), shadow.bary);
}
"#;

/// The kernel's traversals: stackless (a CPU adapter's tuning) with its trail of bits in one
/// word (the BVH is at most 32 levels deep, as every one of these tests' is) or in two (as for
/// a deeper one, `BVH_DEEP`), or with a stack and ordered edge functions (a GPU's).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Traversal {
    Stackless,
    StacklessTwoWords,
    Stack,
}

const TRAVERSALS: [Traversal; 3] = [Traversal::Stackless, Traversal::StacklessTwoWords, Traversal::Stack];

/// Runs the kernel's closest and any queries for `rays` (origin, direction, closest t_max,
/// any t_max) over `tris` with traversal budget `budget`, through `traversal`: (closest t or
/// -1, triangle index in `tris`, any hit, guard tripped) per ray.
fn gpu_queries_with(tris: &[Triangle], rays: &[(Vec3, Vec3, f32, f32)], budget: u32, traversal: Traversal) -> Vec<(f32, u32, bool, bool)> {
    gpu_kernel(tris, rays, budget, "bvh_main", traversal)
}

/// The kernel's brute force (`brute_main`) for `rays` over `tris`, with the edge functions of
/// the traversal it is compared with: (closest t or -1, triangle index in `tris`, false,
/// false) per ray.
fn gpu_brute_force(tris: &[Triangle], rays: &[(Vec3, Vec3, f32, f32)], traversal: Traversal) -> Vec<(f32, u32, bool, bool)> {
    gpu_kernel(tris, rays, u32::MAX, "brute_main", traversal)
}

/// Runs `entry` of the test kernel over `rays` and `tris` (in the BVH's order, indices mapped
/// back to `tris`).
fn gpu_kernel(tris: &[Triangle], rays: &[(Vec3, Vec3, f32, f32)], budget: u32, entry: &str, traversal: Traversal) -> Vec<(f32, u32, bool, bool)> {
    let stackless = traversal != Traversal::Stack;
    use pathlab::gpu::{GpuTriangle, KernelRun};
    use pathlab::shaders::{self, bindings, files};
    let bvh = Bvh::build(tris);
    let gpu_tris: Vec<GpuTriangle> = bvh
        .order
        .iter()
        .map(|&i| {
            let [a, b, c] = tris[i as usize];
            GpuTriangle { p0: a.to_array(), material: 0, p1: b.to_array(), light: u32::MAX, p2: c.to_array(), flags: 0 }
        })
        .collect();
    let ray_data: Vec<[f32; 8]> = rays.iter().map(|(o, d, tc, ta)| [o.x, o.y, o.z, *tc, d.x, d.y, d.z, *ta]).collect();
    let source = shaders::assemble(&[files::COMMON, files::BVH], BVH_KERNEL);
    // Edge functions ordered with the stack (a GPU's tuning, `AdapterTuning`), and wherever the
    // adapter is a GPU: plain ones are watertight only without fused multiply-adds.
    let ordered = !stackless || common::gpu().info.device_type != wgpu::DeviceType::Cpu;
    let constants = [
        ("NUM_TRIANGLES", tris.len() as f64),
        ("TRAVERSAL_BUDGET", budget as f64),
        ("BVH_STACKLESS", stackless as u32 as f64),
        ("BVH_DEEP", (traversal == Traversal::StacklessTwoWords || bvh.depth > pathlab::gpu::ONE_WORD_TRAIL_DEPTH) as u32 as f64),
        ("ORDERED_EDGES", ordered as u32 as f64),
    ];
    let run = KernelRun {
        source: &source,
        entry,
        constants: &constants,
        inputs: vec![(0, bytemuck::cast_slice(&ray_data).to_vec()), (bindings::TRIANGLE_NORMALS.number, vec![0; 48])],
        uniforms: vec![],
        texel_tables: vec![
            (bindings::TRIANGLES.number, bytemuck::cast_slice(&gpu_tris).to_vec()),
            (bindings::BVH_NODES.number, bytemuck::cast_slice(&bvh.records()).to_vec()),
            (bindings::BVH_PARENTS.number, bytemuck::cast_slice(&bvh.pair_parents()).to_vec()),
        ],
        output: (1, rays.len() as u64 * 16),
        workgroups: (rays.len() as u32).div_ceil(64),
    };
    let out: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&run.run(common::gpu()).expect("bvh kernel"));
    out.iter()
        .map(|o| {
            let index = o[1].to_bits();
            let original = if index == u32::MAX { u32::MAX } else { bvh.order[index as usize] };
            (o[0], original, o[2] > 0.5, o[3] > 0.5)
        })
        .collect()
}

#[test]
fn the_kernels_traversal_agrees_with_brute_force_and_is_watertight() {
    let mut rng = Rng(23);
    let mut tris = soup(&mut rng, 3000, (0.01, 0.4), 2.0, Vec3::ZERO);
    // Coplanar and axis-aligned triangles in the soup.
    for k in 0..200 {
        let x = -2.0 + 0.02 * k as f32;
        tris.push([Vec3::new(x, -1.0, 0.5), Vec3::new(x + 0.02, -1.0, 0.5), Vec3::new(x, 1.0, 0.5)]);
    }
    let mut rays: Vec<(Vec3, Vec3, f32, f32)> = random_rays(&mut rng, 100_000, Vec3::ZERO, 3.0).into_iter().map(|(o, d)| (o, d, f32::INFINITY, 0.0)).collect();
    for r in rays.iter_mut() {
        r.3 = brute(&tris, r.0, r.1, f32::INFINITY).map_or(10.0, |t| t * 1.5);
    }
    // The traversal is held to the kernel's own brute force, which shares its arithmetic, on any
    // adapter. On a CPU adapter (lavapipe) that arithmetic is the CPU's, IEEE single precision
    // without contraction, so the kernel's brute force must also give the CPU twin's distances
    // bit for bit. A GPU may fuse multiply-adds and round division and normalisation otherwise
    // (WGSL allows both): on an NVIDIA H200, 19% of these rays' distances differ from the CPU's
    // in the last bits.
    let cpu_arithmetic = common::gpu().info.device_type == wgpu::DeviceType::Cpu;
    let mut hits = 0;
    assert!(Bvh::build(&tris).depth <= pathlab::gpu::ONE_WORD_TRAIL_DEPTH, "the one-word trail is not tested");
    for traversal in TRAVERSALS {
        let kernel_brute = gpu_brute_force(&tris, &rays, traversal);
        hits = kernel_brute.iter().filter(|r| r.0 > 0.0).count();
        let got = gpu_queries_with(&tris, &rays, u32::MAX, traversal);
        let mut mismatches = Vec::new();
        for (k, ((&(o, d, _, any_max), &(t, index, any, exhausted)), &(tb, _, _, _))) in rays.iter().zip(&got).zip(&kernel_brute).enumerate() {
            assert!(!exhausted);
            let expected = brute(&tris, o, d, f32::INFINITY);
            // A tie between triangles at one distance may resolve either way: the distance counts.
            let same = if tb < 0.0 { t < 0.0 } else { t == tb && index != u32::MAX };
            let any_expected = tb > 0.0 && tb < any_max;
            let twin = !cpu_arithmetic || expected.map_or(tb < 0.0, |te| te == tb);
            if !same || any != any_expected || !twin {
                mismatches.push(format!("ray {k}: traversal t {t} (triangle {index}) any {any}, the kernel's brute force t {tb}, the CPU's {expected:?}"));
            }
        }
        assert!(mismatches.is_empty(), "{} of {} rays disagree ({traversal:?}): {:?}", mismatches.len(), rays.len(), &mismatches[..mismatches.len().min(5)]);
    }
    assert!(hits > 20_000, "only {hits} rays hit");

    // Closed mesh: rays from inside aimed at every vertex and edge all hit.
    let mesh = icosphere(3);
    let mut aimed = Vec::new();
    for [a, b, c] in &mesh {
        for target in [*a, *b, *c, (*a + *b) * 0.5, (*b + *c) * 0.5, (*c + *a) * 0.5, *a + (*b - *a) * rng.u()] {
            for origin in [Vec3::ZERO, rng.vec(-0.3, 0.3)] {
                aimed.push((origin, target - origin, f32::INFINITY, 2.0));
            }
        }
    }
    for traversal in TRAVERSALS {
        let got = gpu_queries_with(&mesh, &aimed, u32::MAX, traversal);
        let escaped: Vec<_> = got.iter().zip(&aimed).filter(|((t, _, any, _), _)| *t < 0.0 || !any).map(|(_, r)| *r).collect();
        assert!(escaped.is_empty(), "{} of {} rays through shared edges and vertices escaped ({traversal:?}): {:?}", escaped.len(), aimed.len(), &escaped[..escaped.len().min(3)]);
    }
}

/// The worst case of a traversal: a stack of triangles whose boxes all contain the ray but
/// which it misses (each is cut off just short of the axis), so every node is visited and
/// every triangle tested. With a budget below that, the guard trips; with enough, it does not.
pub fn slivers(n: usize) -> Vec<Triangle> {
    (0..n)
        .map(|k| {
            let z = 1.0 + k as f32 * 1e-3;
            [Vec3::new(-1.0, 1.1, z), Vec3::new(1.0, 1.1, z), Vec3::new(1.0, -0.9, z)]
        })
        .collect()
}

#[test]
fn a_worst_case_traversal_trips_the_guard_and_only_then() {
    let tris = slivers(3000);
    let ray = [(Vec3::ZERO, Vec3::Z, f32::INFINITY, f32::INFINITY)];
    assert!(brute(&tris, Vec3::ZERO, Vec3::Z, f32::INFINITY).is_none(), "the slivers must not cover the axis");
    // The host's bound on the kernel's count of a full traversal (`LoopBound::steps_per_ray`):
    // four per node (visited, climbed out of, a climb started at half of them, three steps),
    // three per leaf, every triangle. A full traversal takes more than half of it.
    let bvh = Bvh::build(&tris);
    let steps = (4 * bvh.nodes.len() + 3 * bvh.nodes.iter().filter(|n| n.count > 0).count()) as u32 + 3000;
    let deep = slivers(100_000);
    for traversal in TRAVERSALS {
        let (t, _, any, exhausted) = gpu_queries_with(&tris, &ray, 2 * steps + 10, traversal)[0];
        assert!(t < 0.0 && !any && !exhausted, "with room for both traversals the guard must stay quiet ({traversal:?})");
        let (_, _, _, exhausted) = gpu_queries_with(&tris, &ray, steps / 2, traversal)[0];
        assert!(exhausted, "a traversal of {steps} steps ran within a budget of {}", steps / 2);
        // The kernel's count stays at or above llvmpipe's own count of loop back-edges, which ends
        // every loop of an invocation at 65535: a traversal far past that, guarded at 60000,
        // trips the guard (were the count lower, llvmpipe would cut the traversal short first, and
        // the ray would silently miss). On a hardware GPU the guard trips as well. (Measured with
        // this scene, 2026-12-04: counting two per leaf and one per climb start, a guard of 55000
        // was already too late; with three and two, a guard of 66000 still trips first.)
        let (t, _, _, exhausted) = gpu_queries_with(&deep, &ray, 60_000, traversal)[0];
        assert!(t < 0.0 && exhausted, "llvmpipe ended the traversal before the guard's count reached 60000 ({traversal:?})");
    }
}

/// The parents the kernel's stackless traversal climbs (`Bvh::pair_parents`): every node but the
/// root is one of a pair (2p + 1, 2p + 2) whose entry p names the node whose children they
/// are; the table is whole texels of four.
#[test]
fn every_node_but_the_root_finds_its_parent() {
    let mut rng = Rng(5);
    for n in [1, 2, 3, 57, 3000] {
        let tris = soup(&mut rng, n, (0.01, 0.4), 2.0, Vec3::ZERO);
        let bvh = Bvh::build(&tris);
        let parents = bvh.pair_parents();
        assert!(!parents.is_empty() && parents.len() % 4 == 0);
        let mut found = 0;
        for (i, node) in bvh.nodes.iter().enumerate().filter(|(_, node)| node.count == 0) {
            assert_eq!(node.first % 2, 1, "node {i}'s children do not start a pair");
            assert_eq!(parents[(node.first as usize - 1) / 2], i as u32);
            found += 2;
        }
        assert_eq!(found, bvh.nodes.len() - 1, "{n} triangles: every node but the root is a child");
    }
}

/// The kernel's node records (`Bvh::records`): an interior node's record holds its children's
/// boxes and, for each child that is a leaf, its triangle range; a leaf's own record its range
/// and the self-leaf flag.
#[test]
fn every_record_holds_its_childrens_boxes_and_leaf_ranges() {
    use pathlab::accel::bvh::{COUNT_BITS, SELF_LEAF};
    use pathlab::accel::BvhRecord;
    // A scene without triangles has one zeroed node (`PackedTriangles`), and one zeroed record.
    let empty = Bvh { nodes: vec![bytemuck::Zeroable::zeroed()], order: Vec::new(), depth: 0 };
    assert_eq!(empty.records(), vec![<BvhRecord as bytemuck::Zeroable>::zeroed()]);
    let mut rng = Rng(9);
    for n in [1, 2, 9, 57, 3000] {
        let tris = soup(&mut rng, n, (0.01, 0.4), 2.0, Vec3::ZERO);
        let bvh = Bvh::build(&tris);
        let records = bvh.records();
        assert_eq!(records.len(), bvh.nodes.len());
        let mask = (1 << COUNT_BITS) - 1;
        for (node, r) in bvh.nodes.iter().zip(&records) {
            if node.count > 0 {
                assert_eq!((r.first_left, r.counts), (node.first, node.count | SELF_LEAF));
                continue;
            }
            let (l, rr) = (&bvh.nodes[node.first as usize], &bvh.nodes[node.first as usize + 1]);
            assert_eq!(r.left, node.first);
            assert_eq!((r.lo_left, r.hi_left, r.lo_right, r.hi_right), (l.lo, l.hi, rr.lo, rr.hi));
            assert_eq!((r.counts & mask, r.counts >> COUNT_BITS), (l.count, rr.count), "no flag on an interior record");
            if l.count > 0 {
                assert_eq!(r.first_left, l.first);
            }
            if rr.count > 0 {
                assert_eq!(r.first_right, rr.first);
            }
        }
    }
}

/// A record counts a leaf's triangles in 15 bits: where no plane separates the centroids (here
/// 100,000 copies of one triangle, which the SAH cannot split), the builder halves the range
/// instead, and every leaf stays within `MAX_LEAF_TRIANGLES`, every triangle in one leaf.
#[test]
fn no_leaf_outgrows_a_records_count() {
    use pathlab::accel::bvh::MAX_LEAF_TRIANGLES;
    let tri = [Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 1.0)];
    let tris = vec![tri; 100_000];
    let bvh = Bvh::build(&tris);
    let leaves: Vec<_> = bvh.nodes.iter().filter(|n| n.count > 0).collect();
    assert!(leaves.iter().all(|n| n.count as usize <= MAX_LEAF_TRIANGLES), "largest leaf {}", leaves.iter().map(|n| n.count).max().unwrap());
    assert_eq!(leaves.iter().map(|n| n.count as usize).sum::<usize>(), tris.len());
    assert_eq!(bvh.closest(&tris, Vec3::new(0.2, 0.2, 0.0), Vec3::Z, f32::INFINITY).map(|h| h.0), Some(1.0));
}

// ----- the small scenes' unrolled tests on shared vertices (generated, bvh.wgsl) -------------

type SmallHit = (f32, u32, [f32; 2]);

/// The path tracer's unrolled small-scene tests (`triangles_brute_force`, each distinct vertex
/// sheared once per ray, the corners `override` constants: `accel::SharedVertices`) for `rays`
/// (origin, direction, t_max) over `tris` in their order, as a closest-hit query and as a shadow
/// ray's, which tests the triangles whose bit `shadow_tests` sets: (t or -1, triangle index,
/// barycentrics of its second and third corners) per ray, for each.
fn gpu_small_scene(tris: &[Triangle], rays: &[(Vec3, Vec3, f32)], shadow_tests: u64) -> Vec<(SmallHit, SmallHit)> {
    use pathlab::accel::SharedVertices;
    use pathlab::gpu::KernelRun;
    use pathlab::shaders::{self, bindings, files};
    let corners: Vec<[[f32; 3]; 3]> = tris.iter().map(|t| t.map(|v| v.to_array())).collect();
    let (shared, positions) = SharedVertices::of(&corners).expect("a small scene");
    let shared = shared.with_shadow_tests(shadow_tests);
    let source = shaders::assemble_unrolled(&[files::COMMON, files::BVH], BVH_KERNEL, tris.len() as u32);
    let ordered = common::gpu().info.device_type != wgpu::DeviceType::Cpu;
    let mut constants = vec![("NUM_TRIANGLES", tris.len() as f64), ("ORDERED_EDGES", ordered as u32 as f64)];
    constants.extend(shaders::small_vertex_constants(&shared));
    let mut vertices: Vec<[f32; 4]> = positions.iter().map(|p| [p[0], p[1], p[2], 0.0]).collect();
    vertices.resize(pathlab::accel::MAX_SHARED_VERTICES as usize, [0.0; 4]);
    let ray_data: Vec<[f32; 8]> = rays.iter().map(|(o, d, t)| [o.x, o.y, o.z, *t, d.x, d.y, d.z, 0.0]).collect();
    let run = KernelRun {
        source: &source,
        entry: "small_main",
        constants: &constants,
        inputs: vec![(0, bytemuck::cast_slice(&ray_data).to_vec())],
        uniforms: vec![(bindings::SMALL_VERTICES.number, bytemuck::cast_slice(&vertices).to_vec())],
        texel_tables: vec![],
        output: (1, rays.len() as u64 * 32),
        workgroups: (rays.len() as u32).div_ceil(64),
    };
    let out: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&run.run(common::gpu()).expect("small-scene kernel"));
    let hit = |o: &[f32; 4]| (o[0], o[1].to_bits(), [o[2], o[3]]);
    out.chunks(2).map(|pair| (hit(&pair[0]), hit(&pair[1]))).collect()
}

/// The small scenes' tests, which shear each distinct vertex once per ray and read every
/// triangle's corners from those (`accel::SharedVertices`), find what the CPU's watertight test
/// finds, triangle by triangle, on a closed icosahedron (20 triangles, 12 vertices) and a strip of
/// quads (12 triangles sharing diagonals and sides) with a stray triangle among them: random
/// rays, and rays aimed at every vertex, edge midpoint and random edge point. On a CPU adapter
/// a random ray's distance must equal the CPU twin's bit for bit (the same operations in the
/// same order), and the triangle it names must give that distance and those barycentrics
/// itself (a tie resolves to either); on any adapter every ray from inside the closed mesh must hit (watertight), and a
/// ray aimed at an edge or vertex the CPU hits must hit at its distance. The shadow rays' query,
/// which leaves out the triangles `SharedVertices::with_shadow_tests` clears (here every third),
/// finds what the CPU finds among the rest, by the same rules.
#[test]
fn the_small_scenes_tests_on_shared_vertices_agree_with_the_cpu_and_are_watertight() {
    let mut rng = Rng(31);
    let mut tris = icosphere(0);
    let closed = tris.len();
    for k in 0..6 {
        let (x0, x1) = (3.0 + k as f32 * 0.5, 3.5 + k as f32 * 0.5);
        let (a, b, c, d) = (Vec3::new(x0, -1.0, 0.2), Vec3::new(x1, -1.0, 0.2), Vec3::new(x1, 1.0, 0.3), Vec3::new(x0, 1.0, 0.3));
        tris.extend([[a, b, c], [a, c, d]]);
    }
    tris.push([Vec3::new(3.2, -0.5, -0.4), Vec3::new(5.0, 0.2, 0.9), Vec3::new(4.1, 0.8, -0.2)]);
    assert!(tris.len() <= pathlab::accel::BRUTE_FORCE_TRIANGLES as usize);
    let corners: Vec<[[f32; 3]; 3]> = tris.iter().map(|t| t.map(|v| v.to_array())).collect();
    let shared = pathlab::accel::SharedVertices::of(&corners).unwrap().0;
    assert_eq!(shared.count, 12 + 14 + 3, "the icosahedron's 12 vertices, the strip's 14, the stray triangle's 3");
    let mut rays: Vec<(Vec3, Vec3, f32)> = Vec::new();
    for (k, [a, b, c]) in tris.iter().enumerate() {
        let targets = [*a, *b, *c, (*a + *b) * 0.5, (*b + *c) * 0.5, (*c + *a) * 0.5, *a + (*b - *a) * rng.u(), *c + (*a - *c) * rng.u()];
        for target in targets {
            let origins = if k < closed { [Vec3::ZERO, rng.vec(-0.3, 0.3)] } else { [Vec3::new(4.5, 0.0, -2.0), rng.vec(2.0, 6.0) - Vec3::new(0.0, 0.0, 8.0)] };
            for origin in origins {
                rays.push((origin, target - origin, f32::INFINITY));
            }
        }
    }
    let aimed = rays.len();
    rays.extend(random_rays(&mut rng, 20_000, Vec3::new(2.0, 0.0, 0.0), 3.0).into_iter().map(|(o, d)| (o, d, f32::INFINITY)));
    // Some with a t_max short of the nearest hit: they must miss.
    for k in 0..2000 {
        let (o, d, _) = rays[aimed + k];
        if let Some(t) = brute(&tris, o, d, f32::INFINITY) {
            rays.push((o, d, t * 0.5));
        }
    }
    // Shadow rays leave every third triangle out (as the faces of a scene's hull:
    // `Scene::shadow_tests_of`), so positions first used by a left-out one are sheared later.
    let shadow_tests = (0..tris.len()).filter(|k| k % 3 != 1).fold(0u64, |m, k| m | 1 << k);
    let kept: Vec<Triangle> = tris.iter().enumerate().filter(|(k, _)| shadow_tests >> k & 1 == 1).map(|(_, t)| *t).collect();
    let got = gpu_small_scene(&tris, &rays, shadow_tests);
    let cpu_arithmetic = common::gpu().info.device_type == wgpu::DeviceType::Cpu;
    let mut mismatches = Vec::new();
    let mut hits = 0;
    for (k, (&(o, d, t_max), &((t, index, bary), (ts, index_s, _)))) in rays.iter().zip(&got).enumerate() {
        // The shadow ray's query: what the CPU finds among the kept triangles, and only those.
        let expected_s = brute(&kept, o, d, t_max);
        let agrees_s = if k < aimed {
            expected_s.is_none_or(|te| ts > 0.0 && (ts - te).abs() <= 1e-6 * te)
        } else if cpu_arithmetic {
            expected_s.map_or(ts < 0.0, |te| te == ts)
        } else {
            expected_s.is_some() == (ts > 0.0)
        };
        if !agrees_s || (ts > 0.0 && shadow_tests >> index_s & 1 == 0) {
            mismatches.push(format!("shadow ray {k} ({o:?} + t {d:?}, t_max {t_max}): kernel t {ts} (triangle {index_s}), the CPU's {expected_s:?} among the kept"));
        }
        let expected = brute(&tris, o, d, t_max);
        hits += (t > 0.0) as usize;
        // The hit triangle's own test gives the kernel's distance (a tie resolves to either).
        let own = (t > 0.0).then(|| {
            let [p0, p1, p2] = tris[index as usize];
            ShearedRay::new(o, d).hit(p0, p1, p2, t_max).map(|h| (h.0, [h.1, h.2]))
        });
        let agrees = if k < aimed {
            // Aimed exactly at an edge or a vertex, where the CPU twin decides a zero edge
            // function in f64 and the kernel does not: the distances may differ in the last
            // bits, and a ray through a mesh's border may hit on one side only.
            expected.is_none_or(|te| t > 0.0 && (t - te).abs() <= 1e-6 * te)
        } else if cpu_arithmetic {
            expected.map_or(t < 0.0, |te| te == t) && own.is_none_or(|h| h == Some((t, bary)))
        } else {
            expected.is_some() == (t > 0.0)
        };
        if !agrees {
            mismatches.push(format!("ray {k} ({o:?} + t {d:?}, t_max {t_max}): kernel t {t} (triangle {index}), the CPU's {expected:?}"));
        }
        // Rays from inside the icosahedron (16 per triangle of it) through its vertices and edges.
        if k < 16 * closed && t < 0.0 {
            mismatches.push(format!("ray {k} from inside the icosahedron, through a vertex or an edge, escaped"));
        }
    }
    assert!(mismatches.is_empty(), "{} of {} rays disagree: {:?}", mismatches.len(), rays.len(), &mismatches[..mismatches.len().min(5)]);
    assert!(hits > 1500, "only {hits} rays hit");
}
