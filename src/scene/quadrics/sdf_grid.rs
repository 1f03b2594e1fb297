//! Mitsuba's `sdfgrid` (`src/shapes/sdfgrid.cpp`; the kernel's is `shaders/quadrics/sdf_grid.wgsl`):
//! the zero set of a signed distance sampled on a grid. The grid's values sit at its nodes, node
//! (i, j, k) at (i / (nx - 1), j / (ny - 1), k / (nz - 1)) of its object space's unit cube (the
//! shape's `to_world` places it); between them the distance is the trilinear interpolant of a
//! cell's eight corners (Dr.Jit's clamped 3D texture lookup at p (n - 1)). Negative is inside,
//! the normal points to positive values. Its values' scale does not matter, only their signs and
//! ratios.
//!
//! - **Intersection** (Mitsuba's LLVM variants, `ray_intersect_preliminary_common_impl`): in
//!   each cell the ray crosses, the interpolant along the ray is a cubic in t (Hansson-Söderlund
//!   et al., JCGT 2022: its coefficients from the cell's corners, `cubic`); the interval is split
//!   at the roots of the cubic's derivative so that one monotone piece holds the first sign
//!   change (Marmitt et al. 2004), where regula falsi finds the root. The nearest root over the
//!   cells is the hit. The host tests every cell whose corners are not all of one sign (as
//!   Mitsuba builds its Embree primitives) and refines the root by bisection to f64's precision;
//!   the kernel walks the cells front to back (3D-DDA) and runs Mitsuba's 51 steps of regula
//!   falsi in the first cell that brackets a root.
//! - **Geometric normal**: the interpolant's gradient (`gradient`), each partial derivative the
//!   difference of two faces of the cell that holds p (the upper one on a face).
//! - **Shading normal** (`normals = "smooth"`, the default; "analytic" uses the geometric one):
//!   the normalised gradients of the eight cells around p's nearest node blended trilinearly
//!   (Hansson-Söderlund et al. 2022's smooth normals, Mitsuba's `smooth`), in object space, then
//!   to the world and normalised.
//! - No uv parametrisation (uv 0, dp/du 0), no area: never a light (as in Mitsuba).
//!
//! Mitsuba mixes x and z up for grids that are not cubes (`update()` reads the voxel sizes in
//! the tensor's z, y, x order); pathlab follows the file's axes, which agree for every cube.

use std::path::PathBuf;
use std::sync::Arc;

use glam::{DVec3, I64Vec3};
use sha2::{Digest, Sha256};

use crate::scene::bsdf_data::BsdfData;

/// Mitsuba's cap on the regula falsi steps in a cell (`sdf_solve_cubic`: until the bracket is
/// under 1e-5 or after 51).
pub const REGULA_FALSI_STEPS: u32 = 51;

/// A grid of signed distances.
#[derive(Debug, Clone)]
pub struct SdfGrid {
    /// The `.vol` file as found.
    pub file: PathBuf,
    /// Nodes along x, y, z (at least 2 each).
    pub res: [u32; 3],
    /// The node values, x fastest, then y, then z.
    pub values: Arc<Vec<f32>>,
    /// SHA-256 of the values (the scene hash's record of the file's content).
    pub content_hash: String,
    /// `normals = "smooth"` (else "analytic").
    pub smooth: bool,
}

impl PartialEq for SdfGrid {
    fn eq(&self, o: &SdfGrid) -> bool {
        self.file == o.file && self.content_hash == o.content_hash && self.smooth == o.smooth
    }
}

impl SdfGrid {
    /// The grid of `values` (`res` nodes, x fastest), or what is wrong with it: fewer than two
    /// nodes along an axis, a value that is not finite, no cell with corners of both signs (or a
    /// zero), where Mitsuba has no primitive to build.
    pub fn new(file: PathBuf, res: [u32; 3], values: Vec<f32>, smooth: bool) -> Result<SdfGrid, String> {
        if res.iter().any(|&n| n < 2) {
            return Err(format!("{} x {} x {} values: a signed distance grid needs at least 2 along each axis (its cells lie between them)", res[0], res[1], res[2]));
        }
        if let Some(i) = values.iter().position(|x| !x.is_finite()) {
            let (nx, ny) = (res[0] as usize, res[1] as usize);
            return Err(format!("value ({}, {}, {}) is {} (a distance must be finite)", i % nx, (i / nx) % ny, i / (nx * ny), values[i]));
        }
        let mut h = Sha256::new();
        for x in &values {
            h.update(x.to_le_bytes());
        }
        let content_hash = format!("{:x}", h.finalize());
        let grid = SdfGrid { file, res, values: Arc::new(values), content_hash, smooth };
        if grid.occupied_cells().next().is_none() {
            return Err("no cell has corners of both signs (or a zero): the grid holds no surface (Mitsuba refuses it too)".into());
        }
        Ok(grid)
    }

    /// Its record in the BSDF data (quadrics/sdf_grid.wgsl): the node counts along x, y, z,
    /// then the values, x fastest; returns where it starts.
    pub fn pack(&self, data: &mut BsdfData) -> u32 {
        let start = data.push(&self.res.map(|n| n as f32));
        data.0.extend(self.values.iter());
        start
    }

    /// Cells along x, y, z (nodes - 1).
    pub fn cells(&self) -> DVec3 {
        DVec3::new(self.res[0] as f64 - 1.0, self.res[1] as f64 - 1.0, self.res[2] as f64 - 1.0)
    }

    /// The value at node (x, y, z), each index clamped to the grid (Dr.Jit's clamp mode).
    fn value(&self, x: i64, y: i64, z: i64) -> f64 {
        let [nx, ny, nz] = self.res.map(|n| n as i64);
        let (x, y, z) = (x.clamp(0, nx - 1), y.clamp(0, ny - 1), z.clamp(0, nz - 1));
        self.values[((z * ny + y) * nx + x) as usize] as f64
    }

    /// The eight corners of cell v, indexed x + 2 y + 4 z.
    fn corners(&self, v: I64Vec3) -> [f64; 8] {
        std::array::from_fn(|c| self.value(v.x + (c & 1) as i64, v.y + ((c >> 1) & 1) as i64, v.z + ((c >> 2) & 1) as i64))
    }

    /// The cells Mitsuba makes primitives of: corners not all > 0 and not all < 0.
    pub fn occupied_cells(&self) -> impl Iterator<Item = I64Vec3> + '_ {
        let c = self.cells();
        let (cx, cy, cz) = (c.x as i64, c.y as i64, c.z as i64);
        (0..cz).flat_map(move |z| (0..cy).flat_map(move |y| (0..cx).map(move |x| I64Vec3::new(x, y, z)))).filter(|&v| {
            let s = self.corners(v);
            !(s.iter().all(|&f| f > 0.0) || s.iter().all(|&f| f < 0.0))
        })
    }

    /// The interpolant at object point p: trilinear in the cell holding p (p (n - 1) in grid
    /// units), clamped beyond the grid.
    pub fn lookup(&self, p: DVec3) -> f64 {
        let g = p * self.cells();
        let i = g.floor();
        let w = g - i;
        let i = i.as_i64vec3();
        let s = self.corners(i);
        let lerp = |a: f64, b: f64, t: f64| a + t * (b - a);
        let y0 = lerp(lerp(s[0], s[1], w.x), lerp(s[2], s[3], w.x), w.y);
        let y1 = lerp(lerp(s[4], s[5], w.x), lerp(s[6], s[7], w.x), w.y);
        lerp(y0, y1, w.z)
    }

    /// The partial derivative along `axis` (0, 1, 2) of the interpolant in the slab of cells
    /// from node `a` to `a + 1` along it, at p's position across it: the difference of the
    /// bilinear values on the slab's two faces, times the cells per unit (Mitsuba's
    /// `voxel_grad`; 0 where both faces clamp to the last node).
    fn slab_derivative(&self, axis: usize, a: i64, p: DVec3) -> f64 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let g = p * self.cells();
        let (iu, iv) = (g[u].floor(), g[v].floor());
        let (wu, wv) = (g[u] - iu, g[v] - iv);
        let face = |k: i64| {
            let at = |du: i64, dv: i64| {
                let mut n = [0i64; 3];
                n[axis] = k;
                n[u] = iu as i64 + du;
                n[v] = iv as i64 + dv;
                self.value(n[0], n[1], n[2])
            };
            let lerp = |a: f64, b: f64, t: f64| a + t * (b - a);
            lerp(lerp(at(0, 0), at(1, 0), wu), lerp(at(0, 1), at(1, 1), wu), wv)
        };
        (face(a + 1) - face(a)) * self.cells()[axis]
    }

    /// The gradient of cell v's interpolant at p (Mitsuba's `voxel_grad`).
    fn cell_gradient(&self, v: I64Vec3, p: DVec3) -> DVec3 {
        DVec3::new(self.slab_derivative(0, v.x, p), self.slab_derivative(1, v.y, p), self.slab_derivative(2, v.z, p))
    }

    /// The interpolant's gradient at object point p, in the cell p (n - 1) truncates to
    /// (Mitsuba's `sdf_grad`: the upper cell on a face), not normalised.
    pub fn gradient(&self, p: DVec3) -> DVec3 {
        self.cell_gradient((p * self.cells()).as_i64vec3(), p)
    }

    /// The smooth normal at object point p, in object space, not normalised: the normalised
    /// gradients of the eight cells around the nearest node r of p (cells r - 1 + (i, j, k)),
    /// those with a negative index counting 0, blended trilinearly by p's position from r - 1/2;
    /// along an axis whose lower (upper) cells are all outside the grid, the upper (lower) ones
    /// alone (Mitsuba's `smooth`).
    pub fn smooth_normal(&self, p: DVec3) -> DVec3 {
        let sp = p * self.cells();
        let r = DVec3::new(sp.x.round_ties_even(), sp.y.round_ties_even(), sp.z.round_ties_even());
        let ri = r.as_i64vec3();
        let mut n = [DVec3::ZERO; 8];
        let mut valid = [false; 8];
        for (c, (n, valid)) in n.iter_mut().zip(valid.iter_mut()).enumerate() {
            let v = ri - I64Vec3::ONE + I64Vec3::new((c & 1) as i64, ((c >> 1) & 1) as i64, ((c >> 2) & 1) as i64);
            *valid = v.min_element() >= 0;
            if *valid {
                *n = self.cell_gradient(v, p).normalize_or_zero();
            }
        }
        let mut w = sp - r + DVec3::splat(0.5);
        for axis in 0..3 {
            let bit = 1 << axis;
            let side = |upper: bool| (0..8).filter(|c| (c & bit != 0) == upper).all(|c| !valid[c]);
            if side(false) {
                w[axis] = 1.0;
            }
            if side(true) {
                w[axis] = 0.0;
            }
        }
        let lerp = |a: DVec3, b: DVec3, t: f64| a * (1.0 - t) + b * t;
        let y0 = lerp(lerp(n[0], n[1], w.x), lerp(n[2], n[3], w.x), w.y);
        let y1 = lerp(lerp(n[4], n[5], w.x), lerp(n[6], n[7], w.x), w.y);
        lerp(y0, y1, w.z)
    }

    /// The nearest t in (t_min, t_max) where the object-space ray o + t d meets the surface.
    pub fn intersect(&self, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<f64> {
        let (og, dg) = (o * self.cells(), d * self.cells());
        self.occupied_cells().filter_map(|v| self.cell_root(v, og, dg)).filter(|&t| t > t_min && t < t_max).min_by(f64::total_cmp)
    }

    /// The first root in cell v of the ray og + t dg in grid units (Mitsuba's per-cell test,
    /// the root refined by bisection).
    fn cell_root(&self, v: I64Vec3, og: DVec3, dg: DVec3) -> Option<f64> {
        let lo = v.as_dvec3();
        let (t0, t1) = slab_interval(og, dg, lo, lo + DVec3::ONE)?;
        let t0 = t0.max(0.0);
        if t0 >= t1 {
            return None;
        }
        let c = cubic(&self.corners(v), og + dg * t0 - lo, dg);
        let (mut a, mut b) = marmitt_bracket(&c, t1 - t0)?;
        // Bisection of the bracket: the sign change stays inside it.
        let fa = eval_cubic(&c, a);
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if m <= a || m >= b {
                break;
            }
            if eval_cubic(&c, m) * fa <= 0.0 {
                b = m;
            } else {
                a = m;
            }
        }
        Some(t0 + if fa == 0.0 { a } else { 0.5 * (a + b) })
    }
}

/// The ray's parameter interval inside the box [lo, hi] (the slab test; an axis the ray runs
/// along contributes nothing where the origin is between its planes), None where it misses.
pub fn slab_interval(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    for a in 0..3 {
        if d[a] == 0.0 {
            if o[a] < lo[a] || o[a] > hi[a] {
                return None;
            }
            continue;
        }
        let (ta, tb) = ((lo[a] - o[a]) / d[a], (hi[a] - o[a]) / d[a]);
        t0 = t0.max(ta.min(tb));
        t1 = t1.min(ta.max(tb));
    }
    (t0 <= t1).then_some((t0, t1))
}

/// The cubic c0 + c1 t + c2 t^2 + c3 t^3 that is minus the trilinear interpolant of a cell's
/// corners `s` (x + 2 y + 4 z) along the ray o + t d in the cell's own coordinates (its corners
/// at 0 and 1): Hansson-Söderlund et al. (JCGT 2022, "Ray tracing of signed distance function
/// grids") as Mitsuba writes it.
pub fn cubic(s: &[f64; 8], o: DVec3, d: DVec3) -> [f64; 4] {
    let (s000, s100, s010, s110, s001, s101, s011, s111) = (s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7]);
    let a = s101 - s001;
    let k0 = s000;
    let k1 = s100 - s000;
    let k2 = s010 - s000;
    let k3 = s110 - s010 - k1;
    let k4 = k0 - s001;
    let k5 = k1 - a;
    let k6 = k2 - (s011 - s001);
    let k7 = k3 - (s111 - s011 - a);
    let m0 = o.x * o.y;
    let m1 = d.x * d.y;
    let m2 = o.x * d.y + o.y * d.x;
    let m3 = k5 * o.z - k1;
    let m4 = k6 * o.z - k2;
    let m5 = k7 * o.z - k3;
    let c0 = (k4 * o.z - k0) + o.x * m3 + o.y * m4 + m0 * m5;
    let c1 = d.x * m3 + d.y * m4 + m2 * m5 + d.z * (k4 + k5 * o.x + k6 * o.y + k7 * m0);
    let c2 = m1 * m5 + d.z * (k5 * d.x + k6 * d.y + k7 * m2);
    let c3 = k7 * m1 * d.z;
    [c0, c1, c2, c3]
}

/// The interpolant (minus the cubic) at t.
pub fn eval_cubic(c: &[f64; 4], t: f64) -> f64 {
    -(((c[3] * t + c[2]) * t + c[1]) * t + c[0])
}

/// The sub-interval of [0, t_end] holding the first sign change of the interpolant, split at
/// the roots of its derivative 3 c3 t^2 + 2 c2 t + c1 (Marmitt et al. 2004, as Mitsuba's
/// `sdf_solve_cubic`), or None where it has none (both ends of one sign, or both zero).
pub fn marmitt_bracket(c: &[f64; 4], t_end: f64) -> Option<(f64, f64)> {
    let (mut t_near, mut t_far) = (0.0, t_end);
    if let Some((r0, r1)) = super::solve_quadratic(3.0 * c[3], 2.0 * c[2], c[1]) {
        if t_near <= r0 && r0 <= t_far {
            if eval_cubic(c, t_near) * eval_cubic(c, r0) <= 0.0 {
                t_far = r0;
            } else {
                t_near = r0;
            }
        }
        if t_near <= r1 && r1 <= t_far {
            if eval_cubic(c, t_near) * eval_cubic(c, r1) <= 0.0 {
                t_far = r1;
            } else {
                t_near = r1;
            }
        }
    }
    let (f_near, f_far) = (eval_cubic(c, t_near), eval_cubic(c, t_far));
    (f_near * f_far <= 0.0 && (f_near != 0.0 || f_far != 0.0)).then_some((t_near, t_far))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Mitsuba's test04 (src/shapes/tests/test_sdfgrid.py): the plane y + z = 1 on 2x2x2 nodes.
    fn plane() -> SdfGrid {
        let h = std::f32::consts::FRAC_1_SQRT_2;
        SdfGrid::new("p.vol".into(), [2, 2, 2], vec![-h, -h, 0.0, 0.0, 0.0, 0.0, h, h], false).unwrap()
    }

    #[test]
    fn a_ray_meets_mitsubas_test_plane_where_mitsubas_test_says() {
        let g = plane();
        for (x, y) in [(0.2, 0.3), (0.7, 0.9), (0.5, 0.05)] {
            let t = g.intersect(DVec3::new(x, y, 3.0), DVec3::NEG_Z, 0.0, f64::INFINITY).unwrap();
            assert!((t - (2.0 + y)).abs() < 1e-12, "{t}");
            let n = g.gradient(DVec3::new(x, y, 1.0 - y)).normalize();
            assert!((n - DVec3::new(0.0, 1.0, 1.0).normalize()).length() < 1e-12, "{n}");
        }
        // Outside the grid's square: nothing.
        assert!(g.intersect(DVec3::new(1.2, 0.5, 3.0), DVec3::NEG_Z, 0.0, f64::INFINITY).is_none());
        assert!(g.intersect(DVec3::new(0.5, 0.5, 3.0), DVec3::NEG_Z, 0.0, 2.0).is_none());
    }

    #[test]
    fn smooth_normals_of_a_plane_are_its_normal_inside_and_mitsubas_blend_at_the_border() {
        // The plane x + 2 y + 2 z = 2.5 (a linear function: every cell's gradient is (1, 2, 2)
        // / 3 per unit) on 5 x 5 x 5 nodes.
        let f = |i: usize, j: usize, k: usize| (i as f64 + 2.0 * j as f64 + 2.0 * k as f64) / 4.0 - 2.5;
        let values = (0..125).map(|c| f(c % 5, (c / 5) % 5, c / 25) as f32).collect();
        let g = SdfGrid::new("p.vol".into(), [5, 5, 5], values, true).unwrap();
        let unit = DVec3::new(1.0, 2.0, 2.0) / 3.0;
        for p in [DVec3::new(0.5, 0.4, 0.35), DVec3::new(0.3, 0.6, 0.4), DVec3::new(0.45, 0.55, 0.3)] {
            assert!((g.smooth_normal(p).normalize() - unit).length() < 1e-6, "{p}: {}", g.smooth_normal(p));
            assert!((g.gradient(p).normalize() - unit).length() < 1e-6);
        }
        // Next to the upper x face, the cells past it (valid for Mitsuba: it checks only
        // negative indices) have no x derivative (both faces clamp to the last node), and pull
        // the blend towards the y-z plane; next to the lower x face the cells before it count 0.
        let upper = g.smooth_normal(DVec3::new(0.95, 0.4, 0.35)).normalize();
        assert!(upper.x < unit.x - 0.05 && upper.y > 0.0, "{upper}");
        let lower = g.smooth_normal(DVec3::new(0.05, 0.4, 0.35)).normalize();
        assert!((lower - unit).length() < 1e-6, "{lower}");
    }

    #[test]
    fn the_cubic_is_the_trilinear_interpolant_along_the_ray() {
        let s = [0.3, -0.2, 0.5, 0.1, -0.4, 0.6, 0.2, -0.7];
        let g = SdfGrid::new("c.vol".into(), [2, 2, 2], s.map(|v| v as f32).to_vec(), true).unwrap();
        let s = g.corners(I64Vec3::ZERO);
        let (o, d) = (DVec3::new(0.1, 0.25, 0.9), DVec3::new(0.3, 0.2, -0.5));
        let c = cubic(&s, o, d);
        for t in [0.0, 0.4, 1.1, 1.6] {
            let direct = g.lookup(o + d * t);
            assert!((eval_cubic(&c, t) - direct).abs() < 1e-12, "{t}: {} against {direct}", eval_cubic(&c, t));
        }
        // The gradient is the interpolant's (central differences).
        let p = DVec3::new(0.4, 0.6, 0.3);
        let h = 1e-6;
        let numeric = DVec3::new(
            (g.lookup(p + DVec3::X * h) - g.lookup(p - DVec3::X * h)) / (2.0 * h),
            (g.lookup(p + DVec3::Y * h) - g.lookup(p - DVec3::Y * h)) / (2.0 * h),
            (g.lookup(p + DVec3::Z * h) - g.lookup(p - DVec3::Z * h)) / (2.0 * h),
        );
        assert!((g.gradient(p) - numeric).length() < 1e-6, "{} against {numeric}", g.gradient(p));
    }

    #[test]
    fn a_grid_without_a_surface_or_with_a_single_node_layer_is_refused() {
        assert!(SdfGrid::new("a.vol".into(), [2, 2, 2], vec![1.0; 8], true).unwrap_err().contains("no cell"));
        assert!(SdfGrid::new("a.vol".into(), [2, 1, 2], vec![1.0, -1.0, 1.0, -1.0], true).unwrap_err().contains("at least 2"));
        assert!(SdfGrid::new("a.vol".into(), [2, 2, 2], vec![1.0, -1.0, 1.0, f32::NAN, 1.0, 1.0, 1.0, 1.0], true).unwrap_err().contains("(1, 1, 0) is NaN"));
    }
}
