//! A bounding volume hierarchy over triangles, built on the CPU with a binned surface area
//! heuristic (12 bins along the widest axis of the centroids, as pbrt-v4's `BVHAggregate`),
//! laid out flat: 32-byte nodes whose two children are adjacent, and a leaf's triangles a
//! contiguous range of `order`; the kernel reads each node as a 64-byte record of its children's
//! boxes (`BvhRecord`, `Bvh::records`). Traversal (here the CPU twin of the kernel's) visits
//! the nearer child first with a stack of at most `MAX_DEPTH` entries: the builder makes a leaf
//! rather than a node deeper than that, so the stack can never overflow.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::triangle::ShearedRay;

/// Deepest node the builder makes (the traversal stack's size).
pub const MAX_DEPTH: usize = 48;
/// Bins of the SAH split search.
const BINS: usize = 12;
/// Triangles a leaf holds at most where splitting is possible and pays: lavapipe's 8 lanes.
const MAX_LEAF: usize = 8;
/// Bits of one leaf's triangle count in a kernel record (`BvhRecord::counts`, where two counts
/// and the `SELF_LEAF` flag share a word).
pub const COUNT_BITS: u32 = 15;
/// Most triangles one leaf holds: the builder splits larger ones, even where the SAH would not.
pub const MAX_LEAF_TRIANGLES: usize = (1 << COUNT_BITS) - 1;
/// `BvhRecord::counts` flag: the record is a leaf's own (reached by a jump or a climb rather than
/// from its parent's record).
pub const SELF_LEAF: u32 = 1 << 31;
/// Texels (16 bytes each) of one `BvhRecord` in the kernel's texel table; bvh.wgsl's
/// `bvh_record` reads them from one row, so the table's width is a multiple of it (asserted
/// beside `shaders::bindings::TEXEL_TABLE_WIDTH`).
pub const RECORD_TEXELS: u32 = 4;
const _: () = assert!(std::mem::size_of::<BvhRecord>() == 16 * RECORD_TEXELS as usize);
/// Cost of visiting a node, relative to one triangle test, in the SAH. Measured on lavapipe
/// (2026-12-05, `scripts/triangle_scaling.sh`, M rays/s against leaves of at most 4 at a node
/// cost of 1): a node step of the stackless traversal (its bounds, the climb, the trail of bits,
/// under the lanes' mask) costs several triangle tests, so fewer, fuller leaves win: 80
/// triangles +10-17%, 1,280 +16-20%, 20,480 +3%, 1.3 M +7-15%, with 3.4 times fewer nodes; node
/// costs 2 and 3 and leaves of 16 gave less (the README's issue-31 table).
const NODE_COST: f32 = 4.0;

/// One node. `count == 0`: an interior node whose children are nodes `first` and `first + 1`;
/// else a leaf of triangles `order[first .. first + count]`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    pub lo: [f32; 3],
    pub first: u32,
    pub hi: [f32; 3],
    pub count: u32,
}

/// Node x's record in the kernel's table (`bvh_record`, bvh.wgsl): four texels. An interior
/// node's record holds its two children's boxes, so that one step of the traversal reads one
/// record (the layout of Aila and Laine 2009), and the triangle ranges of the children that are
/// leaves, so that the step into a leaf child reads nothing more. A leaf's own record (for
/// traversals that arrive at it by a jump or a climb) holds its range and `SELF_LEAF`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct BvhRecord {
    pub lo_left: [f32; 3],
    /// The left child's node index (the right child's is the next).
    pub left: u32,
    pub hi_left: [f32; 3],
    /// The left child's first triangle where it is a leaf (or a leaf's own first triangle).
    pub first_left: u32,
    pub lo_right: [f32; 3],
    /// The right child's first triangle where it is a leaf.
    pub first_right: u32,
    pub hi_right: [f32; 3],
    /// The left child's triangle count (bits 0-14; 0: interior) and the right's (bits 15-29)
    /// where they are leaves; a leaf's own record: its count and `SELF_LEAF`.
    pub counts: u32,
}

/// One step of a traversal (`Bvh::traverse_visiting`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Visit {
    /// An interior node whose two children's boxes are tested: a pass of the kernel's node loop.
    Node(u32),
    /// A triangle tested, by its index in the triangles the BVH was built over.
    Triangle(u32),
}

/// The hierarchy: nodes (the root is node 0) and the triangle order the leaves index.
#[derive(Debug, Clone, PartialEq)]
pub struct Bvh {
    pub nodes: Vec<BvhNode>,
    pub order: Vec<u32>,
    /// Depth of the deepest leaf.
    pub depth: usize,
}

#[derive(Debug, Clone, Copy)]
struct Aabb {
    min: Vec3,
    max: Vec3,
}

impl Aabb {
    const EMPTY: Aabb = Aabb { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) };

    fn grow(self, p: Vec3) -> Aabb {
        Aabb { min: self.min.min(p), max: self.max.max(p) }
    }

    fn union(self, o: Aabb) -> Aabb {
        Aabb { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    /// Half the surface area (the SAH only compares ratios).
    fn half_area(self) -> f32 {
        let d = (self.max - self.min).max(Vec3::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }
}

/// The triangles `[a, b, c]` as the BVH sees them.
pub type Triangle = [Vec3; 3];

fn bounds(t: &Triangle) -> Aabb {
    Aabb::EMPTY.grow(t[0]).grow(t[1]).grow(t[2])
}

impl Bvh {
    /// Builds the hierarchy of `triangles` (at least one).
    pub fn build(triangles: &[Triangle]) -> Bvh {
        let boxes: Vec<Aabb> = triangles.iter().map(bounds).collect();
        let centroids: Vec<Vec3> = boxes.iter().map(|b| (b.min + b.max) * 0.5).collect();
        let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
        let mut nodes = vec![BvhNode::zeroed()];
        let mut depth = 0;
        // (node, first, count, depth) still to build.
        let mut work = vec![(0usize, 0usize, triangles.len(), 0usize)];
        while let Some((node, first, count, d)) = work.pop() {
            depth = depth.max(d);
            let range = &mut order[first..first + count];
            let bb = range.iter().fold(Aabb::EMPTY, |b, &i| b.union(boxes[i as usize]));
            nodes[node].lo = bb.min.to_array();
            nodes[node].hi = bb.max.to_array();
            let mut split = if d + 1 < MAX_DEPTH && count > 1 { sah_split(range, &boxes, &centroids, bb) } else { None };
            // Halves by index where the SAH leaves a leaf too large for a record's count, or the
            // depth left could not bring the range down to one: a node at depth d then holds at
            // most MAX_LEAF_TRIANGLES << (MAX_DEPTH - 1 - d), so one at MAX_DEPTH - 1 fits.
            let halve_above = (MAX_LEAF_TRIANGLES as u64).checked_shl((MAX_DEPTH as u32).saturating_sub(d as u32 + 2)).unwrap_or(u64::MAX);
            if d + 1 < MAX_DEPTH && (count as u64 > halve_above || (split.is_none() && count > MAX_LEAF_TRIANGLES)) {
                split = Some(count / 2);
            }
            match split {
                Some(left) => {
                    let child = nodes.len();
                    nodes.push(BvhNode::zeroed());
                    nodes.push(BvhNode::zeroed());
                    nodes[node].first = child as u32;
                    nodes[node].count = 0;
                    work.push((child, first, left, d + 1));
                    work.push((child + 1, first + left, count - left, d + 1));
                }
                None => {
                    nodes[node].first = first as u32;
                    nodes[node].count = count as u32;
                }
            }
        }
        Bvh { nodes, order, depth }
    }

    /// The kernel's records of the nodes (`BvhRecord`), one per node, in node order.
    pub fn records(&self) -> Vec<BvhRecord> {
        self.nodes
            .iter()
            .map(|n| {
                let mut r = BvhRecord::zeroed();
                if n.count > 0 {
                    r.first_left = n.first;
                    r.counts = n.count | SELF_LEAF;
                    return r;
                }
                if n.first == 0 {
                    // The one zeroed node of a BVH without triangles (no node's children start at 0).
                    return r;
                }
                let (l, rr) = (&self.nodes[n.first as usize], &self.nodes[n.first as usize + 1]);
                debug_assert!(l.count as usize <= MAX_LEAF_TRIANGLES && rr.count as usize <= MAX_LEAF_TRIANGLES);
                r.left = n.first;
                (r.lo_left, r.hi_left, r.lo_right, r.hi_right) = (l.lo, l.hi, rr.lo, rr.hi);
                r.first_left = if l.count > 0 { l.first } else { 0 };
                r.first_right = if rr.count > 0 { rr.first } else { 0 };
                r.counts = l.count | rr.count << COUNT_BITS;
                r
            })
            .collect()
    }

    /// The parents of the nodes, for the kernel's stackless traversal (bvh.wgsl): every node
    /// but the root is one of an adjacent pair (2p + 1, 2p + 2), and entry p is pair p's
    /// parent. Padded with zeros to whole texels of four, at least one.
    pub fn pair_parents(&self) -> Vec<u32> {
        let mut parents = vec![0u32; (self.nodes.len() / 2).div_ceil(4).max(1) * 4];
        for (i, n) in self.nodes.iter().enumerate() {
            // (An interior node's children are at 1 or beyond; a BVH without triangles is one
            // zeroed node.)
            if n.count == 0 && n.first > 0 {
                debug_assert!(n.first % 2 == 1, "children pairs start at odd indices");
                parents[(n.first as usize - 1) / 2] = i as u32;
            }
        }
        parents
    }

    /// The nearest hit of the ray (origin, direction) closer than `t_max`: (t, triangle).
    pub fn closest(&self, triangles: &[Triangle], origin: Vec3, direction: Vec3, t_max: f32) -> Option<(f32, u32)> {
        self.traverse_visiting(triangles, origin, direction, t_max, false, |_| {})
    }

    /// Whether anything lies on the ray closer than `t_max` (shadow rays stop at the first hit).
    pub fn any(&self, triangles: &[Triangle], origin: Vec3, direction: Vec3, t_max: f32) -> bool {
        self.traverse_visiting(triangles, origin, direction, t_max, true, |_| {}).is_some()
    }

    /// The traversal of `closest` (`any`: of `any`, returning the first hit found), in the
    /// kernel's order (the nearer child first), reporting each interior node whose children it
    /// tests and each triangle it tests: what a ray costs (`examples/traversal_coherence.rs`).
    pub fn traverse_visiting(
        &self,
        triangles: &[Triangle],
        origin: Vec3,
        direction: Vec3,
        t_max: f32,
        any: bool,
        mut visit: impl FnMut(Visit),
    ) -> Option<(f32, u32)> {
        let ray = ShearedRay::new(origin, direction);
        let inv = direction.recip();
        let mut best: Option<(f32, u32)> = None;
        let mut t_far = t_max;
        let mut stack = [0u32; MAX_DEPTH];
        let mut top = 0;
        let mut node = 0u32;
        loop {
            let n = &self.nodes[node as usize];
            if n.count > 0 {
                for &i in &self.order[n.first as usize..(n.first + n.count) as usize] {
                    visit(Visit::Triangle(i));
                    let [a, b, c] = triangles[i as usize];
                    if let Some((t, _, _)) = ray.hit(a, b, c, t_far) {
                        best = Some((t, i));
                        t_far = t;
                        if any {
                            return best;
                        }
                    }
                }
            } else {
                visit(Visit::Node(node));
                // The nearer child next, the farther one on the stack.
                let (l, r) = (n.first, n.first + 1);
                let tl = slab(&self.nodes[l as usize], origin, inv, t_far);
                let tr = slab(&self.nodes[r as usize], origin, inv, t_far);
                match (tl, tr) {
                    (Some(a), Some(b)) => {
                        let (near, far) = if a <= b { (l, r) } else { (r, l) };
                        stack[top] = far;
                        top += 1;
                        node = near;
                        continue;
                    }
                    (Some(_), None) => {
                        node = l;
                        continue;
                    }
                    (None, Some(_)) => {
                        node = r;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            if top == 0 {
                return best;
            }
            top -= 1;
            node = stack[top];
        }
    }
}

/// The entry distance of the ray into `node`'s box if it enters before `t_max`. Conservative:
/// the exit distance is widened by 1 + 2 gamma(3) (Ize 2013, "Robust BVH Ray Traversal"), so a
/// triangle the watertight test hits is never culled by its box's rounding.
fn slab(node: &BvhNode, origin: Vec3, inv: Vec3, t_max: f32) -> Option<f32> {
    const GAMMA3: f32 = 3.0 * f32::EPSILON * 0.5 / (1.0 - 3.0 * f32::EPSILON * 0.5);
    let (mut enter, mut exit) = (0.0f32, t_max);
    for k in 0..3 {
        let (lo, hi, o) = (node.lo[k], node.hi[k], origin[k]);
        if inv[k].is_infinite() {
            // Parallel to this slab: inside it all along, or never.
            if o < lo || o > hi {
                return None;
            }
            continue;
        }
        let (t0, t1) = ((lo - o) * inv[k], (hi - o) * inv[k]);
        enter = enter.max(t0.min(t1));
        exit = exit.min(t0.max(t1) * (1.0 + 2.0 * GAMMA3));
    }
    (enter <= exit).then_some(enter)
}

/// The SAH split of `range` (reordered in place): the number of triangles that go left, or
/// `None` when a leaf is cheaper (or nothing separates the centroids).
fn sah_split(range: &mut [u32], boxes: &[Aabb], centroids: &[Vec3], bb: Aabb) -> Option<usize> {
    let cb = range.iter().fold(Aabb::EMPTY, |b, &i| b.grow(centroids[i as usize]));
    let extent = cb.max - cb.min;
    let axis = if extent.x >= extent.y && extent.x >= extent.z { 0 } else if extent.y >= extent.z { 1 } else { 2 };
    if !(extent[axis] > 0.0) {
        // Every centroid in one point: no plane separates them.
        return None;
    }
    let bin_of = |i: u32| (((centroids[i as usize][axis] - cb.min[axis]) / extent[axis] * BINS as f32) as usize).min(BINS - 1);
    let mut bins = [(Aabb::EMPTY, 0usize); BINS];
    for &i in range.iter() {
        let b = &mut bins[bin_of(i)];
        *b = (b.0.union(boxes[i as usize]), b.1 + 1);
    }
    // Cost of splitting after bin k: sweep from both ends.
    let mut left = [(Aabb::EMPTY, 0usize); BINS - 1];
    let mut acc = (Aabb::EMPTY, 0);
    for k in 0..BINS - 1 {
        acc = (acc.0.union(bins[k].0), acc.1 + bins[k].1);
        left[k] = acc;
    }
    let mut acc = (Aabb::EMPTY, 0);
    let mut best = (f32::INFINITY, 0);
    for k in (0..BINS - 1).rev() {
        acc = (acc.0.union(bins[k + 1].0), acc.1 + bins[k + 1].1);
        let (l, r) = (left[k], acc);
        if l.1 == 0 || r.1 == 0 {
            continue;
        }
        let cost = NODE_COST + (l.0.half_area() * l.1 as f32 + r.0.half_area() * r.1 as f32) / bb.half_area().max(f32::MIN_POSITIVE);
        if cost < best.0 {
            best = (cost, k);
        }
    }
    let leaf_cost = range.len() as f32;
    if !best.0.is_finite() || (range.len() <= MAX_LEAF && leaf_cost <= best.0) {
        return None;
    }
    // Partition: bins 0..=k to the left.
    let mut i = 0;
    for j in 0..range.len() {
        if bin_of(range[j]) <= best.1 {
            range.swap(i, j);
            i += 1;
        }
    }
    Some(i)
}
