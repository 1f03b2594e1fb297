// bvh.wgsl — triangles and the bounding volume hierarchy over them (built on the host, whose
// `Bvh::closest` and `Bvh::any` are this traversal's CPU twins, checked against brute force). An
// interior node's two children are adjacent nodes; a leaf's triangles are a contiguous range of
// `triangles` (the host stores them in leaf order). Each node is read as one 64-byte record of
// its children's boxes (BvhRecord). Traversal visits the nearer child first and keeps the
// farther on a stack or in a trail of bits, one per level, BVH_MAX_DEPTH levels at most
// (bvh_traverse).

// Triangles of the scene (0: the mesh code compiles out), and whether any has vertex normals.
override NUM_TRIANGLES: u32 = 0u;
override HAS_SHADING_NORMALS: bool = false;
// The BVH traversal without a stack (bvh_traverse_stackless), else with one.
override BVH_STACKLESS: bool = true;
// Edge functions in one order for both triangles of an edge (edge_function).
override ORDERED_EDGES: bool = true;
// The BVH has a leaf deeper than 32 levels (`gpu::ONE_WORD_TRAIL_DEPTH`): the stackless
// traversal's trail of bits, one bit per level from the root to the current node, takes two
// words, else one (set by the host from `Bvh::depth`; true where it is not known).
override BVH_DEEP: bool = true;
// Most traversal steps (nodes visited, leaves entered twice, triangles tested) one invocation
// may take in all:
// where the host cannot bound traversal within llvmpipe's loop limit, the kernel counts them
// and a sample that would exceed this is dropped from its pixel (the readback then refuses the
// image with the reason). 0xffffffff: no guard.
override TRAVERSAL_BUDGET: u32 = 0xffffffffu;

// Flags of a triangle: TRIANGLE_TWO_SIDED, TRIANGLE_HAS_NORMALS (generated from
// src/shaders/flags.rs).

struct Triangle {
    p0: vec3f,
    material: u32,
    p1: vec3f,
    // Index of the light this triangle is (INVALID: not emissive).
    light: u32,
    p2: vec3f,
    flags: u32,
}

struct TriangleNormals {
    n0: vec3f,
    _pad0: u32,
    n1: vec3f,
    _pad1: u32,
    n2: vec3f,
    _pad2: u32,
}

// Texture coordinates at the three vertices.
struct TriangleUvs {
    uv0: vec2f,
    uv1: vec2f,
    uv2: vec2f,
}

// Node x's record (`accel::BvhRecord`): an interior node's children's boxes, so that a traversal
// step reads one record (Aila and Laine 2009), with the triangle ranges of the children that are
// leaves, so that the step into a leaf child reads nothing more; a leaf's own record (reached by
// a jump or a climb) has its range as the left child's and BVH_SELF_LEAF in `counts`.
struct BvhRecord {
    lo_left: vec3f,
    // The left child's node (the right child's is the next).
    left: u32,
    hi_left: vec3f,
    // The left child's first triangle where it is a leaf.
    first_left: u32,
    lo_right: vec3f,
    first_right: u32,
    hi_right: vec3f,
    // The children's triangle counts where they are leaves (0: interior), BVH_COUNT_BITS each,
    // left in the low bits; or a leaf's own count and BVH_SELF_LEAF.
    counts: u32,
}

// A leaf: its triangles first .. first + count (count 0: none).
struct BvhLeaf {
    first: u32,
    count: u32,
}

// The triangles (three texels each) and the BVH's node records (four each) are texel tables
// (src/shaders/bindings.rs, `Kind::TexelTable`): rgba32uint texels of TEXEL_TABLE_WIDTH per
// row, read by `triangle_record` and `bvh_record`. The traversal reads them at a per-lane index
// in its inner loop, where lavapipe serves a texel as one branch-free 16-byte load per lane and
// a storage-buffer record as a loop over the lanes with two branches per lane and component.
@group(0) @binding(BINDING_TRIANGLES) var triangles: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(BINDING_TRIANGLE_NORMALS) var<storage, read> triangle_normals: array<TriangleNormals>;
@group(0) @binding(BINDING_TRIANGLE_UVS) var<storage, read> triangle_uvs: array<TriangleUvs>;
@group(0) @binding(BINDING_BVH_NODES) var bvh_nodes: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(BINDING_BVH_PARENTS) var bvh_parents: texture_storage_2d<rgba32uint, read>;

// Triangle i of the table, its bits as the host wrote them (texels 3i, 3i + 1, 3i + 2): a hit's
// or a light's, at an index that differs per lane, also in small scenes (lavapipe reads the
// three texels as three 16-byte loads per lane, where a uniform copy cost a load per lane and
// component).
fn triangle_record(i: u32) -> Triangle {
    let a = textureLoad(triangles, texel_coords(3u * i));
    let b = textureLoad(triangles, texel_coords(3u * i + 1u));
    let c = textureLoad(triangles, texel_coords(3u * i + 2u));
    return Triangle(bitcast<vec3f>(a.xyz), a.w, bitcast<vec3f>(b.xyz), b.w, bitcast<vec3f>(c.xyz), c.w);
}

// The record of node i of the BVH (texels 4i to 4i + 3: BVH_RECORD_TEXELS, generated).
fn bvh_record(i: u32) -> BvhRecord {
    // The four texels lie in one row (the host asserts that TEXEL_TABLE_WIDTH is a multiple of
    // BVH_RECORD_TEXELS), so their coordinates are computed once.
    let at = texel_coords(BVH_RECORD_TEXELS * i);
    let a = textureLoad(bvh_nodes, at);
    let b = textureLoad(bvh_nodes, at + vec2u(1u, 0u));
    let c = textureLoad(bvh_nodes, at + vec2u(2u, 0u));
    let e = textureLoad(bvh_nodes, at + vec2u(3u, 0u));
    return BvhRecord(bitcast<vec3f>(a.xyz), a.w, bitcast<vec3f>(b.xyz), b.w, bitcast<vec3f>(c.xyz), c.w, bitcast<vec3f>(e.xyz), e.w);
}

// The left child's leaf in record r, or a leaf's own (count 0: the left child is interior).
fn bvh_leaf_left(r: BvhRecord) -> BvhLeaf {
    return BvhLeaf(r.first_left, r.counts & ((1u << BVH_COUNT_BITS) - 1u));
}

// The right child's leaf in record r (count 0: interior).
fn bvh_leaf_right(r: BvhRecord) -> BvhLeaf {
    return BvhLeaf(r.first_right, (r.counts >> BVH_COUNT_BITS) & ((1u << BVH_COUNT_BITS) - 1u));
}
// Scenes of at most BRUTE_FORCE_TRIANGLES triangles (generated from src/accel/mod.rs) also
// have their distinct vertex positions (`accel::SharedVertices`) in a uniform buffer. Where the
// module unrolls their tests (SMALL_TRIANGLE_TESTS, generated: on CPU adapters only,
// `gpu::AdapterTuning`), the kernel tests every triangle in turn at lane-uniform indices, each
// position sheared once per ray, instead of traversing the BVH: on SIMD CPU drivers a
// divergent traversal of a small BVH through per-lane loads costs more than testing every
// triangle from a buffer served as one broadcast load (the Cornell box: 36 triangles). On a
// GPU the copy each invocation keeps lives in local memory, and the BVH is far faster. A hit's
// own triangle is read from the texel table (`triangle_record`).
@group(0) @binding(BINDING_SMALL_VERTICES) var<uniform> small_vertices: array<vec4f, MAX_SHARED_VERTICES>;

// The shading normal of triangle i at barycentrics `bary` (of p1 and p2): its vertex normals
// interpolated where it has them, else n, its unit winding normal.
fn triangle_shading_normal(i: u32, tri: Triangle, n: vec3f, bary: vec2f) -> vec3f {
    if (HAS_SHADING_NORMALS && (tri.flags & TRIANGLE_HAS_NORMALS) != 0u) {
        let tn = triangle_normals[i];
        let interpolated = (1.0 - bary.x - bary.y) * tn.n0 + bary.x * tn.n1 + bary.y * tn.n2;
        return select(n, normalize(interpolated), dot(interpolated, interpolated) > 0.0);
    }
    return n;
}

// The uv parametrisation of triangle i at barycentrics `bary` (of p1 and p2), as Mitsuba's
// meshes have it: its vertices' texture coordinates interpolated where it has them, else the
// barycentrics themselves.
fn triangle_uv(i: u32, tri: Triangle, bary: vec2f) -> vec2f {
    if ((tri.flags & TRIANGLE_HAS_UVS) != 0u) {
        let t = triangle_uvs[i];
        return (1.0 - bary.x - bary.y) * t.uv0 + bary.x * t.uv1 + bary.y * t.uv2;
    }
    return bary;
}

// The direction of dp/du of triangle i, whose unit winding normal is n, as Mitsuba's meshes have
// it (mesh.cpp): from its vertices' texture coordinates where it has them,
//   dp/du = (duv1.y dp0 - duv0.y dp1) / det,  det = duv0.x duv1.y - duv0.y duv1.x,
// with dp0 = p1 - p0, dp1 = p2 - p0, duv0 = uv1 - uv0, duv1 = uv2 - uv0 (where det is 0, the first
// axis of the arbitrary frame of n, Mitsuba's coordinate_system); else p1 - p0 (the barycentric
// parametrisation).
fn triangle_tangent(i: u32, tri: Triangle, n: vec3f) -> vec3f {
    return triangle_partials(i, tri, n).du;
}

// dp/du and dp/dv of triangle i, whose unit winding normal is n, as Mitsuba's meshes have them
// (mesh.cpp), for bump maps and tangent frames (triangle_tangent): from its texture coordinates
// where it has them,
//   dp/du = (duv1.y dp0 - duv0.y dp1) / det,  dp/dv = (duv0.x dp1 - duv1.x dp0) / det,
// (where det is 0, the arbitrary frame of n, Mitsuba's coordinate_system); else p1 - p0 and
// p2 - p0 (the barycentric parametrisation).
fn triangle_partials(i: u32, tri: Triangle, n: vec3f) -> Partials {
    let dp0 = tri.p1 - tri.p0;
    let dp1 = tri.p2 - tri.p0;
    if ((tri.flags & TRIANGLE_HAS_UVS) != 0u) {
        let t = triangle_uvs[i];
        let duv0 = t.uv1 - t.uv0;
        let duv1 = t.uv2 - t.uv0;
        let det = duv0.x * duv1.y - duv0.y * duv1.x;
        if (det == 0.0) {
            let f = frame_from_normal(n);
            return Partials(f.t, f.b);
        }
        return Partials((duv1.y * dp0 - duv0.y * dp1) / det, (duv0.x * dp1 - duv1.x * dp0) / det);
    }
    return Partials(dp0, dp1);
}

// Barycentrics (of p1 and p2) of a point p in the triangle's plane (plane_barycentrics,
// common.wgsl).
fn triangle_barycentrics(tri: Triangle, p: vec3f) -> vec2f {
    return plane_barycentrics(tri.p0, tri.p1, tri.p2, p);
}

// Whether the triangle emits along w, a direction arriving at a point of it whose shading normal
// is n_s: on the side n_s faces, or on both where it is two-sided. Mitsuba decides the emitting
// side in the shading frame (Frame3f::cos_theta(si.wi) > 0 in its area emitter); for a
// triangle without vertex normals that is the side of its winding normal cross(p1 - p0, p2 - p0).
fn triangle_emits_along(tri: Triangle, n_s: vec3f, w: vec3f) -> bool {
    return dot(n_s, w) < 0.0 || (tri.flags & TRIANGLE_TWO_SIDED) != 0u;
}

// Traversal steps taken by this invocation so far, and whether the guard stopped one.
var<private> traversal_steps: u32;
var<private> traversal_exhausted: bool;

// The watertight ray-triangle test (Woop, Benthin and Wald 2013): shear the ray onto +z, map
// the vertices likewise, decide by the signs of the three 2D edge functions. Two triangles that
// share an edge compute its edge function from the same sheared vertices with opposite signs,
// so a ray through the edge is never outside both. The permutation (kx, ky, kz) and the shear
// are per ray, computed once (ShearedRay).
struct ShearedRay {
    origin: vec3f,
    k: vec3u,
    shear: vec3f,
}

fn sheared_ray(o: vec3f, d: vec3f) -> ShearedRay {
    let a = abs(d);
    var kz = 2u;
    if (a.x > a.y) {
        if (a.x > a.z) { kz = 0u; }
    } else if (a.y > a.z) {
        kz = 1u;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kz + 2u) % 3u;
    // Swapped for a negative dominant component, which keeps the winding.
    if (d[kz] < 0.0) {
        let t = kx;
        kx = ky;
        ky = t;
    }
    return ShearedRay(o, vec3u(kx, ky, kz), vec3f(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]));
}

// The 2D edge function q.x p.y - q.y p.x of sheared vertices p and q. With ORDERED_EDGES it is
// computed in one order for both directions of the edge (its ends ordered lexicographically)
// and negated exactly for the other: the two triangles sharing an edge then get exactly
// opposite values even where the driver fuses a product into a multiply-add, which WGSL allows
// (an NVIDIA H200 does: rays through shared edges escaped there). The test's watertightness
// rests on that antisymmetry. Without fusion (lavapipe, whose kernel matches the CPU twin bit
// for bit) the plain difference already has it, and the ordering would cost the Cornell box
// 14% more kernel instructions (callgrind, 183.5 M -> 209.8 M): the host sets ORDERED_EDGES on
// GPUs only (`gpu::AdapterTuning`); both give the same value there, bit for bit.
fn edge_function(p: vec2f, q: vec2f) -> f32 {
    if (!ORDERED_EDGES) {
        return q.x * p.y - q.y * p.x;
    }
    let swap = p.x > q.x || (p.x == q.x && p.y > q.y);
    let a = select(p, q, swap);
    let b = select(q, p, swap);
    let e = b.x * a.y - b.y * a.x;
    return select(e, -e, swap);
}

// Vertex p in the ray's space: translated to its origin, its axes permuted by the ray's
// dominant one, x and y sheared so the ray runs along z, and z scaled by the ray's 1 / d_z.
fn shear_vertex(r: ShearedRay, p: vec3f) -> vec3f {
    let a = p - r.origin;
    return vec3f(a[r.k.x] - r.shear.x * a[r.k.z], a[r.k.y] - r.shear.y * a[r.k.z], r.shear.z * a[r.k.z]);
}

// Distance along the ray to the triangle of sheared corners a, b, c (shear_vertex) if it is hit
// in (0, t_max), else -1; barycentrics of b and c in `bary`.
fn intersect_sheared(a: vec3f, b: vec3f, c: vec3f, t_max: f32, bary: ptr<function, vec2f>) -> f32 {
    // Scaled barycentrics: the edge functions.
    let u = edge_function(b.xy, c.xy);
    let v = edge_function(c.xy, a.xy);
    let w = edge_function(a.xy, b.xy);
    let det = u + v + w;
    // The hit's distance scaled by det, compared without a division.
    let t = u * a.z + v * b.z + w * c.z;
    // Hit where the edge functions share det's sign (none of another sign: the point is inside
    // or on an edge) and t / det lies in (0, t_max). With each value's sign flipped where det is
    // negative (exact), that is three comparisons: every edge function >= 0 and
    // 0 < t < t_max |det|; det = 0 fails the last two (t_max |det| is 0, or NaN for an infinite
    // t_max), as a degenerate or edge-on triangle must. On the Cornell box this took the
    // kernel from 514 M to 424-429 M instructions (README, "Meshes on lavapipe").
    let sign = bitcast<u32>(det) & 0x80000000u;
    let uvw = bitcast<vec3f>(bitcast<vec3u>(vec3f(u, v, w)) ^ vec3u(sign));
    let t_signed = bitcast<f32>(bitcast<u32>(t) ^ sign);
    // The smallest edge function by selects (`ordered_min`), which compile to the SIMD minimum
    // (WGSL's min may add NaN handling: none is needed, a NaN failing every comparison either
    // way).
    let uvw_min = ordered_min(ordered_min(uvw.x, uvw.y), uvw.z);
    if (!(uvw_min >= 0.0 && t_signed > 0.0 && t_signed < t_max * abs(det))) {
        return -1.0;
    }
    let inv = 1.0 / det;
    *bary = vec2f(v, w) * inv;
    return t * inv;
}

// Distance to the triangle along the ray if it is hit in (0, t_max), else -1; barycentrics of
// p1 and p2 in `bary`.
fn intersect_triangle(r: ShearedRay, p0: vec3f, p1: vec3f, p2: vec3f, t_max: f32, bary: ptr<function, vec2f>) -> f32 {
    return intersect_sheared(shear_vertex(r, p0), shear_vertex(r, p1), shear_vertex(r, p2), t_max, bary);
}

// A ray as the box tests read it: its origin, the reciprocal of its direction, and the axes it
// is parallel to (1/d infinite). Made once per traversal, outside its loops: lavapipe's LLVM
// passes hoist nothing out of a loop (Mesa 22.3 gallivm runs no LICM), so what a box test
// derives from the ray alone would be derived again in every pass.
struct NodeRay {
    o: vec3f,
    inv_d: vec3f,
    parallel: vec3<bool>,
}

fn node_ray(o: vec3f, d: vec3f) -> NodeRay {
    let inv_d = 1.0 / d;
    return NodeRay(o, inv_d, abs(inv_d) >= vec3f(INFINITY));
}

// Entry distance of the ray into a node's box if it enters before t_max, else -1. The exit
// distance is widened by 1 + 2 gamma(3) (Ize 2013), so rounding never culls a box whose
// triangle the watertight test hits. On an axis the ray is parallel to (1/d infinite) the slab
// distances would be 0 * inf = NaN where the origin lies on a slab plane: that axis instead
// holds the ray when the origin is within the slab, all along or never, as on the CPU.
fn intersect_node(lo: vec3f, hi: vec3f, ray: NodeRay, t_max: f32) -> f32 {
    let o = ray.o;
    let parallel = ray.parallel;
    let t0 = select((lo - o) * ray.inv_d, vec3f(-INFINITY), parallel);
    let t1 = select((hi - o) * ray.inv_d, vec3f(INFINITY), parallel);
    let within = all(!parallel | ((o >= lo) & (o <= hi)));
    // Minima and maxima by selects (common.wgsl's `ordered_min`, `ordered_max`): no value here
    // is NaN (the slab distances of a finite box and origin are finite or infinite, t_max is a
    // distance), and WGSL's min and max would add NaN handling, a compare and a blend per
    // component, for both children in every pass of the node loop.
    let near = ordered_min_vec(t0, t1);
    let far = ordered_max_vec(t0, t1) * 1.0000004;
    let enter = ordered_max(ordered_max(near.x, near.y), ordered_max(near.z, 0.0));
    let exit = ordered_min(ordered_min(far.x, far.y), ordered_min(far.z, t_max));
    return select(-1.0, enter, within && enter <= exit);
}

struct TriangleHit {
    t: f32,
    // Index into `triangles`, INVALID on a miss.
    index: u32,
    bary: vec2f,
}

// Counts one traversal step against the guard; false once the budget is spent.
fn traversal_step() -> bool {
    traversal_steps += 1u;
    if (traversal_steps > TRAVERSAL_BUDGET) {
        traversal_exhausted = true;
        return false;
    }
    return true;
}

// The small scenes' tests, `load_small_triangles()`, `triangles_brute_force_nearest(o, d,
// t_max)` and `triangles_brute_force_shadow(o, d, t_max)` (and, for test kernels,
// `triangles_brute_force(o, d, t_max, shadow)`, either), are generated after this file
// (src/shaders/generated.rs): one step per triangle at constant indices, SMALL_TRIANGLE_TESTS
// of them (the module is assembled per triangle count; steps past NUM_TRIANGLES fold away).
// Every entry point that traces rays calls `load_small_triangles()` first, outside any branch
// or loop (through `load_scene_registers()`,
// which copies the spheres, planes and quadrics the same way). Why, on lavapipe (Mesa 22.3,
// gallivm): inside a branch or loop even a constant-index uniform read is compiled as 8
// lane-by-lane loads (LLVM could not merge them here), and at a loop counter's index always
// (gallivm has no divergence analysis); before any branch, a constant-index read is one load
// for all 8 lanes, and the copy then lives in registers and stack slots. On the Cornell box
// (36 triangles, `mis`, 64x64 at 64 spp, same image bit for bit) the kernel took 5.91 G
// instructions with a loop over the uniform array, 3.11 G unrolled, 2.91 G unrolled from the
// copy; see the README's "How the kernel is made fast".

// The nearest triangle along (o, d) closer than t_max (brute force for small scenes, else the
// BVH).
fn triangles_closest(o: vec3f, d: vec3f, t_max: f32) -> TriangleHit {
    if (NUM_TRIANGLES <= SMALL_TRIANGLE_TESTS) {
        return triangles_brute_force_nearest(o, d, t_max);
    }
    return bvh_traverse(o, d, t_max, false);
}

// The first triangle found along (o, d) closer than t_max: shadow rays towards lights, which in
// small scenes skip the faces of the scene's hull and of closed convex meshes turned away from
// every light (`Scene::shadow_tests_of`).
fn triangles_any(o: vec3f, d: vec3f, t_max: f32) -> TriangleHit {
    if (NUM_TRIANGLES <= SMALL_TRIANGLE_TESTS) {
        return triangles_brute_force_shadow(o, d, t_max);
    }
    return bvh_traverse(o, d, t_max, true);
}

// The parent of node x >= 1. Children come in adjacent pairs (2p + 1, 2p + 2); entry p of
// `bvh_parents` (four per texel) is pair p's parent.
fn bvh_parent(x: u32) -> u32 {
    let p = (x - 1u) >> 1u;
    return textureLoad(bvh_parents, texel_coords(p >> 2u))[p & 3u];
}

// The other node of x's pair.
fn bvh_sibling(x: u32) -> u32 {
    return ((x - 1u) ^ 1u) + 1u;
}

// Tests the triangles of a leaf in turn, keeping the nearest hit in `best`; with `any`, stops
// at the first. Each triangle is one step of the traversal guard.
fn bvh_test_leaf(ray: ShearedRay, leaf: BvhLeaf, best: ptr<function, TriangleHit>, any: bool) {
    let end = leaf.first + leaf.count;
    for (var i = leaf.first; i < end; i++) {
        if (!traversal_step()) {
            break;
        }
        let tri = triangle_record(i);
        var bary: vec2f;
        let t = intersect_triangle(ray, tri.p0, tri.p1, tri.p2, (*best).t, &bary);
        if (t > 0.0) {
            *best = TriangleHit(t, i, bary);
            if (any) {
                break;
            }
        }
    }
}

// The entry distances of the ray into the children of the interior node of record r (-1:
// missed, or entered beyond t_max).
fn bvh_enter_children(r: BvhRecord, ray: NodeRay, t_max: f32) -> vec2f {
    return vec2f(intersect_node(r.lo_left, r.hi_left, ray, t_max), intersect_node(r.lo_right, r.hi_right, ray, t_max));
}

// The nearest triangle along (o, d) closer than t_max through the BVH; with `any`, the first
// one found (shadow rays): stackless on CPU adapters, with a stack on GPUs (BVH_STACKLESS, set
// by the host: `gpu::pipeline::AdapterTuning`). Both visit the nodes in the same order and find
// the same hits.
fn bvh_traverse(o: vec3f, d: vec3f, t_max: f32, any: bool) -> TriangleHit {
    if (BVH_STACKLESS) {
        return bvh_traverse_stackless(o, d, t_max, any);
    }
    return bvh_traverse_stack(o, d, t_max, any);
}

// The traversal with a stack of the farther children, BVH_MAX_DEPTH entries (the deepest node
// the builder makes). On an NVIDIA H200 it is faster than the stackless one (2026-12-04,
// `pathlab bench ... --methods mis`, 1024x1024: 80-triangle icosphere 3748 against 3250 M
// samples/s, 1.3 M triangles 642 against 446, Veach's scene 698 against 633).
fn bvh_traverse_stack(o: vec3f, d: vec3f, t_max: f32, any: bool) -> TriangleHit {
    var best = TriangleHit(t_max, INVALID, vec2f(0.0));
    let ray = sheared_ray(o, d);
    let boxes = node_ray(o, d);
    var stack: array<u32, BVH_MAX_DEPTH>;
    var top = 0u;
    var node = 0u;
    loop {
        if (!traversal_step()) {
            break;
        }
        let r = bvh_record(node);
        var next = INVALID;
        var leaf = BvhLeaf(0u, 0u);
        if ((r.counts & BVH_SELF_LEAF) != 0u) {
            leaf = bvh_leaf_left(r);
        } else {
            // The nearer child next (its triangles now, where it is a leaf), the farther on the
            // stack.
            let l = r.left;
            let rr = r.left + 1u;
            let entry = bvh_enter_children(r, boxes, best.t);
            let tl = entry.x;
            let tr = entry.y;
            var near_left = false;
            if (tl >= 0.0 && tr >= 0.0) {
                near_left = tl <= tr;
                next = select(rr, l, near_left);
                stack[top] = select(l, rr, near_left);
                top++;
            } else if (tl >= 0.0) {
                near_left = true;
                next = l;
            } else if (tr >= 0.0) {
                next = rr;
            }
            if (next != INVALID) {
                if (near_left) {
                    leaf = bvh_leaf_left(r);
                } else {
                    leaf = bvh_leaf_right(r);
                }
                if (leaf.count > 0u) {
                    next = INVALID;
                }
            }
        }
        if (leaf.count > 0u) {
            // Entering a leaf's loop costs llvmpipe about two back-edges of its own (measured:
            // tests/bvh.rs), counted here so that the guard always trips first.
            traversal_steps += 2u;
            bvh_test_leaf(ray, leaf, &best, any);
            if (any && best.index != INVALID) {
                break;
            }
        }
        if (next == INVALID) {
            if (top == 0u) {
                break;
            }
            top--;
            next = stack[top];
        }
        node = next;
    }
    return best;
}

// The trail of bits (x: its lower word; y: the levels past 32, always 0 unless BVH_DEEP), with
// the functions that move it. Where the BVH is at most 32 levels deep they work on one word:
// lavapipe runs the second word's shifts and selects under the lanes' mask in every pass
// otherwise.

// One level down, the new level's bit `bit`.
fn trail_down(trail: vec2u, bit: u32) -> vec2u {
    if (BVH_DEEP) {
        return vec2u((trail.x << 1u) | bit, (trail.y << 1u) | (trail.x >> 31u));
    }
    return vec2u((trail.x << 1u) | bit, 0u);
}

// One level up.
fn trail_up(trail: vec2u) -> vec2u {
    if (BVH_DEEP) {
        return vec2u((trail.x >> 1u) | (trail.y << 31u), trail.y >> 1u);
    }
    return vec2u(trail.x >> 1u, 0u);
}

// Whether no level's farther child waits.
fn trail_empty(trail: vec2u) -> bool {
    if (BVH_DEEP) {
        return all(trail == vec2u(0u));
    }
    return trail.x == 0u;
}

// The levels up to the deepest one whose farther child waits (the trail is not empty).
fn trail_trailing_zeros(trail: vec2u) -> u32 {
    if (BVH_DEEP) {
        return select(32u + countTrailingZeros(trail.y), countTrailingZeros(trail.x), trail.x != 0u);
    }
    return countTrailingZeros(trail.x);
}

// The trail shifted up by z < 64 levels (z < 32 unless BVH_DEEP).
fn trail_shifted(trail: vec2u, z: u32) -> vec2u {
    if (!BVH_DEEP) {
        return vec2u(trail.x >> z, 0u);
    }
    if (z >= 32u) {
        return vec2u(trail.y >> (z - 32u), 0u);
    }
    return vec2u((trail.x >> z) | select(0u, trail.y << ((32u - z) & 31u), z > 0u), trail.y >> z);
}

// The stackless traversal (after Hapala et al. 2011 and Áfra and Szirmay-Kalos 2014): the nodes
// still to visit are a trail of bits, one per level from the root down to the current node, set
// where that level's farther child waits. Descending shifts a bit in; where no child is entered,
// the traversal goes up to the deepest level whose bit is set and over to the farther child
// there. That is the order a stack of farther children gives, so every hit is the one the stack
// found (`Bvh::closest`); but the trail lives in two registers, where a private array indexed per
// lane costs lavapipe a store or load per lane with a branch each (80-triangle icosphere +36%
// samples/s, Veach's scene +45%). Levels: at most BVH_MAX_DEPTH (48), in a 64-bit trail.
//
// How it goes over to the waiting child (2026-12-06, README "Meshes on lavapipe"):
// - The last eight farther children pushed are also kept in two vec4u registers, shifted by
//   selects (constant indices only, so no per-lane memory). Where one is kept, the traversal
//   jumps to it: the levels it goes up are the trail's trailing zeros. Only where the eight have
//   overflowed does it climb the parents (`bvh_parent`), a texel load per level.
// - The loops are while-while (Aila and Laine 2009): an inner loop walks interior nodes to the
//   next leaf, then the leaf's triangles are tested, once every lane has left the inner loop;
//   climbs run in the outer loop too. lavapipe runs a loop's whole body, every branch under the
//   lanes' mask, for as long as any lane is in it, and a nested loop at least once: with a leaf
//   or a climb inside the node loop, every node step paid for a leaf's tests and a climb.
//
// The guard counts a step per pass of the inner loop, per triangle tested and per level climbed,
// and what llvmpipe charges beyond them for entering a loop: three per leaf, three per climb
// (llvmpipe counts every pass of every loop, the one that leaves it included, and enters a
// nested loop at least once; measured on the worst case of tests/bvh.rs).
// `LoopBound::steps_per_ray` bounds the sum. llvmpipe's count is kept per SIMD group of 8 lanes
// (one limiter per run of its compiled function: Mesa 22.3, lp_bld_ir_common.c), the guard's per
// lane: where a group's lanes take turns (one walks the inner loop while the others wait at
// their leaves), the group's passes exceed its busiest lane's. The host's budget leaves a
// quarter of the limit for that (render/renderer.rs); tests/bvh.rs measures one ray.
fn bvh_traverse_stackless(o: vec3f, d: vec3f, t_max: f32, any: bool) -> TriangleHit {
    var best = TriangleHit(t_max, INVALID, vec2f(0.0));
    let ray = sheared_ray(o, d);
    let boxes = node_ray(o, d);
    var trail = vec2u(0u);
    var node = 0u;
    // Whether the traversal leaves `node` before its next step (a leaf tested, or a node whose
    // children were both missed), and whether it must climb the parents to do so.
    var leave = false;
    var climb = false;
    // The farther children pushed last, newest in recent_a.x; 0 marks an empty slot (node 0,
    // the root, is no node's child).
    var recent_a = vec4u(0u);
    var recent_b = vec4u(0u);
    loop {
        if (climb) {
            // Up the parents to the deepest level whose farther child waits, and over to it.
            traversal_steps += 2u;
            while ((trail.x & 1u) == 0u) {
                traversal_steps += 1u;
                trail = trail_up(trail);
                node = bvh_parent(node);
            }
            node = bvh_sibling(node);
            trail.x ^= 1u;
            leave = false;
            climb = false;
        }
        // Through interior nodes to the next leaf (count 0: none is left, the traversal must
        // climb, or the guard stopped it).
        var leaf = BvhLeaf(0u, 0u);
        loop {
            if (!traversal_step()) {
                break;
            }
            if (leave) {
                if (trail_empty(trail)) {
                    break;
                }
                if (recent_a.x == 0u) {
                    traversal_steps += 1u;
                    climb = true;
                    break;
                }
                // Over to the newest farther child kept: up as many levels as the trail's
                // trailing zeros, then that level's bit cleared (its farther child taken).
                trail = trail_shifted(trail, trail_trailing_zeros(trail));
                trail.x ^= 1u;
                node = recent_a.x;
                recent_a = vec4u(recent_a.yzw, recent_b.x);
                recent_b = vec4u(recent_b.yzw, 0u);
                leave = false;
            }
            let rec = bvh_record(node);
            if ((rec.counts & BVH_SELF_LEAF) != 0u) {
                // A leaf reached by a jump or a climb.
                leaf = bvh_leaf_left(rec);
                break;
            }
            // The nearer child next; where both are entered, the farther one's bit set and the
            // child kept.
            let l = rec.left;
            let r = rec.left + 1u;
            let entry = bvh_enter_children(rec, boxes, best.t);
            let tl = entry.x;
            let tr = entry.y;
            leave = tl < 0.0 && tr < 0.0;
            if (!leave) {
                let both = tl >= 0.0 && tr >= 0.0;
                let near_left = tl >= 0.0 && (tr < 0.0 || tl <= tr);
                trail = trail_down(trail, select(0u, 1u, both));
                node = select(r, l, near_left);
                if (both) {
                    recent_b = vec4u(recent_a.w, recent_b.xyz);
                    recent_a = vec4u(select(l, r, near_left), recent_a.xyz);
                }
                // Where the nearer child is a leaf, its range is in this record: its triangles
                // are tested next without a step to its own.
                let ll = bvh_leaf_left(rec);
                let lr = bvh_leaf_right(rec);
                let near_count = select(lr.count, ll.count, near_left);
                if (near_count > 0u) {
                    leaf = BvhLeaf(select(lr.first, ll.first, near_left), near_count);
                    break;
                }
            }
        }
        if (climb) {
            continue;
        }
        if (leaf.count == 0u) {
            break;
        }
        traversal_steps += 3u;
        bvh_test_leaf(ray, leaf, &best, any);
        if (any && best.index != INVALID) {
            break;
        }
        leave = true;
    }
    return best;
}
