//! Mitsuba's `bsplinecurve` (`src/shapes/bsplinecurve.cpp`; the kernel's is
//! `shaders/quadrics/bspline_curve.wgsl`): tubes along uniform cubic B-splines whose radius is a
//! cubic B-spline too. A curve of n control points (p_i, r_i) has n - 3 segments, segment k the
//! B-spline of points k .. k + 3 over v in [0, 1]:
//!
//!   c(v) = ((1 - v)^3 p0 + (3v^3 - 6v^2 + 4) p1 + (-3v^3 + 3v^2 + 3v + 1) p2 + v^3 p3) / 6,
//!
//! r(v) alike. The curve does not reach its end points, and its ends are open (no caps: Mitsuba
//! says so, and Embree's and OptiX's round B-splines have none). The surface is the sweep of
//! the circles of radius r(v) in the planes normal to the centre line: its points p satisfy
//!
//!   (p - c(v)) . c'(v) = 0 and |p - c(v)|^2 = r(v)^2
//!
//! for some v, the two equations whose gradient is Mitsuba's normal
//! (|c'|^2 - (p - c) . c'') (p - c) - r r' c'. Back faces are culled, as for linear curves.
//!
//! Mitsuba intersects through Embree (subdivision and Newton steps); pathlab finds each segment's
//! candidates on a chain of swept spheres along the centre line (`pieces` chords of it, their
//! radii widened by `margin`, the farthest the true tube strays from the chain: it lies inside
//! them), and solves the two equations along the ray, (t, v), by Newton's method from the nearest
//! two candidates. The hit is a solution with v in [0, 1] whose normal faces the ray. The host
//! (f64, 64 pieces, Newton from every candidate) is the reference the kernel (f32,
//! `BSPLINE_PIECES`, the two nearest) is tested against.
//!
//! uv as Mitsuba's: u the angle around the tangent at the hit (`angle_frame` of c'(v)), v =
//! (v + segment) / segments over all the file's curves; dp/du = 2 pi r (T x n).

use std::f64::consts::TAU;

use glam::{DAffine3, DVec3};

use super::linear_curve::{angle_frame, CurveSegment};

/// Chords of a segment's centre line in the kernel's candidate search.
pub const BSPLINE_PIECES: u32 = 16;
/// Newton steps from each candidate in the kernel.
pub const BSPLINE_NEWTON_STEPS: u32 = 8;
/// How far outside [0, 1] a hit's v may lie and count: at a joint both segments' solutions
/// then count (in f32 each may land a rounding outside its own), at an open end the tube is
/// 1e-5 of a segment longer.
pub const BSPLINE_V_SLACK: f64 = 1e-5;

/// One segment of a B-spline curve in world space.
#[derive(Debug, Clone, PartialEq)]
pub struct BsplineSegment {
    /// Its four control points and radii.
    pub p: [DVec3; 4],
    pub r: [f64; 4],
    /// Its number among the shape's segments (all its file's curves, in order).
    pub index: u32,
    /// The shape's number of segments.
    pub count: u32,
    /// How far the tube strays outside the chain of `BSPLINE_PIECES` swept spheres along its
    /// centre line's chords (`margin`), widened by half.
    pub margin: f32,
}

/// The centre line and radius of a segment at v, with their derivatives.
#[derive(Debug, Clone, Copy)]
pub struct BsplinePoint {
    pub c: DVec3,
    pub dc: DVec3,
    pub ddc: DVec3,
    pub r: f64,
    pub dr: f64,
}

/// The segments of `curves` (each at least four points) with their points moved by `to_world`
/// (the radii kept, as Mitsuba does), numbered in order.
pub fn bspline_segments(curves: &[Vec<[f64; 4]>], to_world: &DAffine3) -> Vec<BsplineSegment> {
    let count: usize = curves.iter().map(|c| c.len() - 3).sum();
    curves
        .iter()
        .flat_map(|c| c.windows(4))
        .enumerate()
        .map(|(index, w)| {
            let p = std::array::from_fn(|i| to_world.transform_point3(DVec3::new(w[i][0], w[i][1], w[i][2])));
            let r = std::array::from_fn(|i| w[i][3]);
            let mut s = BsplineSegment { p, r, index: index as u32, count: count as u32, margin: 0.0 };
            s.margin = (1.5 * s.chain_distance(BSPLINE_PIECES) + 1e-5 * s.scale()) as f32;
            s
        })
        .collect()
}

/// The uniform cubic B-spline basis at v and its first two derivatives.
fn basis(v: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let (v2, v3) = (v * v, v * v * v);
    let b = [(1.0 - v).powi(3) / 6.0, (3.0 * v3 - 6.0 * v2 + 4.0) / 6.0, (-3.0 * v3 + 3.0 * v2 + 3.0 * v + 1.0) / 6.0, v3 / 6.0];
    let db = [-(1.0 - v).powi(2) / 2.0, (3.0 * v2 - 4.0 * v) / 2.0, (-3.0 * v2 + 2.0 * v + 1.0) / 2.0, v2 / 2.0];
    let ddb = [1.0 - v, 3.0 * v - 2.0, 1.0 - 3.0 * v, v];
    (b, db, ddb)
}

impl BsplineSegment {
    /// The centre line and radius at v.
    pub fn at(&self, v: f64) -> BsplinePoint {
        let (b, db, ddb) = basis(v);
        let sum = |w: &[f64; 4]| (0..4).fold(DVec3::ZERO, |a, i| a + self.p[i] * w[i]);
        let sum_r = |w: &[f64; 4]| (0..4).map(|i| self.r[i] * w[i]).sum::<f64>();
        BsplinePoint { c: sum(&b), dc: sum(&db), ddc: sum(&ddb), r: sum_r(&b), dr: sum_r(&db) }
    }

    /// The size of its coordinates (for absolute tolerances).
    fn scale(&self) -> f64 {
        self.p.iter().map(|p| p.abs().max_element()).fold(1.0, f64::max)
    }

    /// Piece i of `pieces` chords: the swept sphere from c(i / n) to c((i + 1) / n), radii r
    /// there plus `margin`.
    pub fn piece(&self, i: u32, pieces: u32, margin: f64) -> CurveSegment {
        let (a, b) = (self.at(i as f64 / pieces as f64), self.at((i + 1) as f64 / pieces as f64));
        CurveSegment { p0: a.c, r0: a.r.max(0.0) + margin, p1: b.c, r1: b.r.max(0.0) + margin, index: i, count: pieces, first: true }
    }

    /// The farthest the tube's circles reach outside the chain of swept spheres on `pieces`
    /// chords (sampled densely): a centre's distance from its chord plus its radius above the
    /// chord's linear one.
    fn chain_distance(&self, pieces: u32) -> f64 {
        let mut worst = 0.0f64;
        for i in 0..pieces {
            let (a, b) = (self.at(i as f64 / pieces as f64), self.at((i + 1) as f64 / pieces as f64));
            let chord = b.c - a.c;
            for k in 1..32 {
                let s = k as f64 / 32.0;
                let q = self.at((i as f64 + s) / pieces as f64);
                let along = ((q.c - a.c).dot(chord) / chord.length_squared().max(1e-300)).clamp(0.0, 1.0);
                let off = (q.c - (a.c + chord * along)).length();
                worst = worst.max(off + (q.r - (a.r + (b.r - a.r) * along)).max(0.0));
            }
        }
        worst
    }

    /// The nearest t in (t_min, t_max) where the ray o + t d enters the tube, with its v: Newton
    /// from every entry into a chain of 64 widened swept spheres (the reference).
    pub fn intersect(&self, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<(f64, f64)> {
        let pieces = 64;
        let margin = 1.5 * self.chain_distance(pieces) + 1e-9 * self.scale();
        (0..pieces)
            .filter_map(|i| {
                let piece = self.piece(i, pieces, margin);
                let t = piece.intersect(o, d, f64::NEG_INFINITY, t_max)?;
                let v = (i as f64 + piece.v_local(o + d * t)) / pieces as f64;
                self.solve(o, d, t.max(t_min), v, 40)
            })
            .filter(|&(t, _)| t > t_min && t < t_max)
            .min_by(|a, b| a.0.total_cmp(&b.0))
    }

    /// Newton's method on (p - c(v)) . c'(v) = 0, |p - c(v)|^2 = r(v)^2 with p = o + t d, from
    /// (t, v); the solution if it converged with v in [0, 1] (give or take `BSPLINE_V_SLACK`) and
    /// its normal facing the ray.
    pub fn solve(&self, o: DVec3, d: DVec3, mut t: f64, mut v: f64, steps: u32) -> Option<(f64, f64)> {
        for _ in 0..steps {
            let b = self.at(v);
            let q = o + d * t - b.c;
            let (f1, f2) = (q.dot(b.dc), q.dot(q) - b.r * b.r);
            let (j00, j01) = (d.dot(b.dc), -b.dc.dot(b.dc) + q.dot(b.ddc));
            let (j10, j11) = (2.0 * q.dot(d), -2.0 * q.dot(b.dc) - 2.0 * b.r * b.dr);
            let det = j00 * j11 - j01 * j10;
            if det == 0.0 || !det.is_finite() {
                return None;
            }
            t -= (f1 * j11 - f2 * j01) / det;
            v -= (j00 * f2 - j10 * f1) / det;
            if !(v > -1.0 && v < 2.0) {
                return None;
            }
        }
        let b = self.at(v);
        let q = o + d * t - b.c;
        let tolerance = 1e-7 * (b.r + 1e-3 * self.scale());
        let converged = (q.length() - b.r).abs() <= tolerance && q.dot(b.dc).abs() <= tolerance * b.dc.length();
        (converged && (-BSPLINE_V_SLACK..=1.0 + BSPLINE_V_SLACK).contains(&v) && self.normal_at(o + d * t, v).dot(d) < 0.0).then_some((t, v))
    }

    /// The parameter of the circle a point p of the surface lies on: where (p - c(v)) . c'(v)
    /// changes sign nearest p's closest sample, refined by Newton's method.
    pub fn v_of(&self, p: DVec3) -> f64 {
        let mut v = (0..=64).map(|k| k as f64 / 64.0).min_by(|a, b| (p - self.at(*a).c).length_squared().total_cmp(&(p - self.at(*b).c).length_squared())).unwrap_or(0.5);
        for _ in 0..30 {
            let b = self.at(v);
            let q = p - b.c;
            let g = q.dot(b.dc);
            let dg = -b.dc.dot(b.dc) + q.dot(b.ddc);
            if dg == 0.0 {
                break;
            }
            v = (v - g / dg).clamp(0.0, 1.0);
        }
        v
    }

    /// Mitsuba's normal at point p of the surface on the circle of v:
    /// (|c'|^2 - (p - c) . c'') (p - c) - r r' c', normalised.
    pub fn normal_at(&self, p: DVec3, v: f64) -> DVec3 {
        let b = self.at(v);
        let q = p - b.c;
        ((b.dc.length_squared() - q.dot(b.ddc)) * q - b.r * b.dr * b.dc).normalize()
    }

    /// Mitsuba's uv at point p of the surface on the circle of v.
    pub fn uv_at(&self, p: DVec3, v: f64) -> [f64; 2] {
        let b = self.at(v);
        let (u_rot, u_rad) = angle_frame(b.dc.normalize());
        let n = (p - b.c).normalize();
        let mut u = u_rot.dot(n).atan2(u_rad.dot(n));
        if u < 0.0 {
            u += TAU;
        }
        [u / TAU, (v + self.index as f64) / self.count as f64]
    }

    /// The corners of its box: its control points +- their radii (the curve lies in their hull).
    pub fn box_corners(&self) -> [DVec3; 8] {
        let lo = (0..4).fold(DVec3::INFINITY, |a, i| a.min(self.p[i] - DVec3::splat(self.r[i])));
        let hi = (0..4).fold(DVec3::NEG_INFINITY, |a, i| a.max(self.p[i] + DVec3::splat(self.r[i])));
        std::array::from_fn(|c| DVec3::new(if c & 1 == 0 { lo.x } else { hi.x }, if c & 2 == 0 { lo.y } else { hi.y }, if c & 4 == 0 { lo.z } else { hi.z }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn straight() -> BsplineSegment {
        // Evenly spaced collinear points along x: the centre line is the x axis, radius 0.5.
        let p = [DVec3::new(-1.0, 0.0, 0.0), DVec3::ZERO, DVec3::X, DVec3::new(2.0, 0.0, 0.0)];
        bspline_segments(&[p.iter().map(|p| [p.x, p.y, p.z, 0.5]).collect()], &DAffine3::IDENTITY).remove(0)
    }

    #[test]
    fn a_straight_segment_is_an_open_cylinder_from_its_second_to_its_third_point() {
        let s = straight();
        assert!(s.margin < 1e-4, "{}", s.margin);
        // From above, at x = 0.25: v = 0.25 on the unit-speed line.
        let (t, v) = s.intersect(DVec3::new(0.25, 0.0, 3.0), DVec3::NEG_Z, 0.0, f64::INFINITY).unwrap();
        assert!((t - 2.5).abs() < 1e-9 && (v - 0.25).abs() < 1e-9, "{t} {v}");
        assert!((s.normal_at(DVec3::new(0.25, 0.0, 0.5), v) - DVec3::Z).length() < 1e-9);
        // Beyond the segment's ends: open, no caps.
        assert!(s.intersect(DVec3::new(1.1, 0.0, 3.0), DVec3::NEG_Z, 0.0, f64::INFINITY).is_none());
        // Along the axis, from outside the end: it looks through the open tube.
        assert!(s.intersect(DVec3::new(-3.0, 0.0, 0.0), DVec3::X, 0.0, f64::INFINITY).is_none());
        // From inside: back faces only.
        assert!(s.intersect(DVec3::new(0.5, 0.0, 0.0), DVec3::Z, 0.0, f64::INFINITY).is_none());
        assert!((s.v_of(DVec3::new(0.7, 0.5, 0.0)) - 0.7).abs() < 1e-9);
        let uv = s.uv_at(DVec3::new(0.25, 0.0, 0.5), 0.25);
        // u_rot is +z for a tangent along x: the top of the tube is a quarter turn.
        assert!((uv[0] - 0.25).abs() < 1e-9 && (uv[1] - 0.25).abs() < 1e-9, "{uv:?}");
    }

    #[test]
    fn on_a_bent_segment_of_varying_radius_hits_lie_on_their_circles_and_the_normal_is_the_surfaces() {
        let pts = [[0.0, 0.0, 0.0, 0.1], [1.0, 1.0, 0.0, 0.3], [2.0, 0.0, 0.5, 0.2], [3.0, 1.0, 0.0, 0.05]];
        let s = bspline_segments(&[pts.to_vec()], &DAffine3::IDENTITY).remove(0);
        let mut hits = 0;
        for k in 0..40 {
            let v0 = 0.05 + 0.9 * k as f64 / 40.0;
            let b = s.at(v0);
            let o = b.c + DVec3::new(0.3, 0.2, 4.0);
            let d = (b.c + DVec3::new(0.0, 0.003 * k as f64, 0.0) - o).normalize();
            let Some((t, v)) = s.intersect(o, d, 0.0, f64::INFINITY) else { continue };
            hits += 1;
            let p = o + d * t;
            let c = s.at(v);
            assert!(((p - c.c).length() - c.r).abs() < 1e-9 && (p - c.c).dot(c.dc).abs() < 1e-9);
            assert!((s.v_of(p) - v).abs() < 1e-7);
            // The normal is the surface's: p + e tangent vectors stay on it to first order.
            let n = s.normal_at(p, v);
            let h = 1e-5;
            for (dt, dv) in [(h, 0.0), (0.0, h)] {
                // A nearby surface point: a step along the circle and along v.
                let c2 = s.at(v + dv);
                let rad = (p - c.c).normalize();
                let side = c.dc.normalize().cross(rad);
                let q = c2.c + (rad + side * dt).normalize().reject_from(c2.dc).normalize() * c2.r;
                assert!(n.dot(q - p).abs() < 1e-3 * (q - p).length().max(1e-12), "{k}: normal off the surface");
            }
        }
        assert_eq!(hits, 40, "every ray aimed within the radius hits");
    }
}

