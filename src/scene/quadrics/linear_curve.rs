//! Mitsuba's `linearcurve` (`src/shapes/linearcurve.cpp`; the kernel's is
//! `shaders/quadrics/linear_curve.wgsl`): tubes along polylines whose radius varies linearly
//! along each segment, joined and ended by spheres. Each segment from (p0, r0) to (p1, r1) is
//! the sphere swept along it, the convex hull of its two end spheres (Embree's and OptiX's
//! "round linear curve", which Mitsuba renders through): the cone tangent to both spheres, and
//! the spheres. Mitsuba has no intersector of its own; what it defines is the hit's frame:
//!
//! - the contact sphere's parameter v_local in [0, 1] (for a point p of the cone,
//!   ((p - p0) . d + r0 (r1 - r0)) / (|d|^2 - (r1 - r0)^2), d = p1 - p0; 0 or 1 on the end
//!   spheres), and the normal n = normalize(p - c), c = lerp(p0, p1, v_local);
//! - uv: u the angle around the segment's axis a, atan2(u_rot . n, u_rad . n) / 2 pi in [0, 1),
//!   u_rot the world's +z made orthogonal to a ((0, 1, 0) where a is exactly +-z), u_rad = u_rot
//!   x a; v = (v_local + segment) / segments, along all the file's curves in order;
//! - dp/du = 2 pi a x (p - c), dp/dv = segments ((p1 - p0) + (r1 - r0) n).
//!
//! Back faces are culled (Mitsuba builds Embree so): a ray meets a tube only where it enters
//! it, and a ray from inside a tube meets nothing of it.
//!
//! The file (Mitsuba's format): one control point per line, `x y z radius`; a blank line starts
//! a new curve; a curve has at least two points. `to_world` moves the points, not the radii.

use std::f64::consts::TAU;

use glam::{DAffine3, DVec3};

/// One segment of a linear curve in world space.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveSegment {
    pub p0: DVec3,
    pub r0: f64,
    pub p1: DVec3,
    pub r1: f64,
    /// Its number among the shape's segments (all its file's curves, in order).
    pub index: u32,
    /// The shape's number of segments.
    pub count: u32,
    /// It starts its curve: its start sphere is its own. A later segment's start sphere is the
    /// previous one's end sphere, which alone reports the joint (Embree's neighbour rule): the
    /// joint's hit, and its uv, are the previous segment's, whatever the rounding.
    pub first: bool,
}

/// The curves of a curve file's text, each its control points (x, y, z, radius), each of at
/// least `min_points` (a linear curve 2, a B-spline 4), or the 1-based line and what is wrong
/// there.
pub fn read_curves(text: &str, min_points: usize) -> Result<Vec<Vec<[f64; 4]>>, (usize, String)> {
    let mut curves: Vec<Vec<[f64; 4]>> = Vec::new();
    let mut current: Vec<[f64; 4]> = Vec::new();
    let mut start_line = 1;
    let finish = |current: &mut Vec<[f64; 4]>, curves: &mut Vec<Vec<[f64; 4]>>, start_line: usize| -> Result<(), (usize, String)> {
        if !current.is_empty() && current.len() < min_points {
            let points = if current.len() == 1 { "one control point".to_string() } else { format!("{} control points", current.len()) };
            let kind = if min_points == 2 { "linear curve" } else { "B-spline curve" };
            return Err((start_line, format!("a curve of {points}: a {kind} needs at least {min_points}")));
        }
        if !current.is_empty() {
            curves.push(std::mem::take(current));
        }
        Ok(())
    };
    for (k, line) in text.split('\n').enumerate() {
        let words: Vec<&str> = line.split_whitespace().collect();
        if words.is_empty() {
            finish(&mut current, &mut curves, start_line)?;
            continue;
        }
        if current.is_empty() {
            start_line = k + 1;
        }
        if words.len() < 4 {
            return Err((k + 1, format!("a control point is `x y z radius` (got {} number(s): {:?})", words.len(), line.trim())));
        }
        let mut point = [0.0; 4];
        for (c, w) in words.iter().take(4).enumerate() {
            match w.parse::<f64>() {
                Ok(v) if v.is_finite() => point[c] = v,
                _ => return Err((k + 1, format!("could not read {:?} as a finite number (a control point is `x y z radius`)", w))),
            }
        }
        if !(point[3] >= 0.0) {
            return Err((k + 1, format!("radius {} is negative", point[3])));
        }
        current.push(point);
    }
    finish(&mut current, &mut curves, start_line)?;
    if curves.is_empty() {
        return Err((1, "no control points: the file defines no curve".to_string()));
    }
    Ok(curves)
}

/// The segments of `curves` with their points moved by `to_world` (the radii kept, as Mitsuba
/// does), numbered in order.
pub fn segments(curves: &[Vec<[f64; 4]>], to_world: &DAffine3) -> Vec<CurveSegment> {
    let count: usize = curves.iter().map(|c| c.len() - 1).sum();
    let point = |p: &[f64; 4]| (to_world.transform_point3(DVec3::new(p[0], p[1], p[2])), p[3]);
    curves
        .iter()
        .flat_map(|c| c.windows(2).enumerate())
        .enumerate()
        .map(|(index, (k, w))| {
            let ((p0, r0), (p1, r1)) = (point(&w[0]), point(&w[1]));
            CurveSegment { p0, r0, p1, r1, index: index as u32, count: count as u32, first: k == 0 }
        })
        .collect()
}

impl CurveSegment {
    /// The segment's unit axis.
    pub fn axis(&self) -> DVec3 {
        (self.p1 - self.p0).normalize()
    }

    /// t where the ray o + t d enters the swept sphere, if in (t_min, t_max): the cone tangent to
    /// both end spheres where the contact lies between them, else the nearer end sphere
    /// (Quilez's rounded-cone intersection); an entry on the start sphere only where the segment
    /// starts its curve (`first`; else the previous segment reports it). Exits are back faces,
    /// culled.
    pub fn intersect(&self, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<f64> {
        let ba = self.p1 - self.p0;
        let oa = o - self.p0;
        let ob = o - self.p1;
        let rr = self.r0 - self.r1;
        let (m0, m1, m2, m3, m4, m5, m6, m7) = (ba.dot(ba), ba.dot(oa), ba.dot(d), d.dot(oa), d.dot(d), oa.dot(oa), ob.dot(d), ob.dot(ob));
        let d2 = m0 - rr * rr;
        let k2 = d2 * m4 - m2 * m2;
        let k1 = d2 * m3 - m1 * m2 + m2 * rr * self.r0;
        let k0 = d2 * m5 - m1 * m1 + 2.0 * m1 * rr * self.r0 - m0 * self.r0 * self.r0;
        let h = k1 * k1 - k0 * k2;
        if h < 0.0 {
            return None;
        }
        let t = (-h.sqrt() - k1) / k2;
        let y = m1 - self.r0 * rr + t * m2;
        let (entry, on_start) = if y > 0.0 && y < d2 {
            (t, false)
        } else {
            let h0 = m3 * m3 - m4 * (m5 - self.r0 * self.r0);
            let h1 = m6 * m6 - m4 * (m7 - self.r1 * self.r1);
            let t0 = if h0 > 0.0 { (-m3 - h0.sqrt()) / m4 } else { f64::INFINITY };
            let t1 = if h1 > 0.0 { (-m6 - h1.sqrt()) / m4 } else { f64::INFINITY };
            (t0.min(t1), t0 < t1)
        };
        (entry > t_min && entry < t_max && (self.first || !on_start)).then_some(entry)
    }

    /// The contact sphere's parameter at a point p of the surface, in [0, 1].
    pub fn v_local(&self, p: DVec3) -> f64 {
        let d = self.p1 - self.p0;
        let dr = self.r1 - self.r0;
        (((p - self.p0).dot(d) + self.r0 * dr) / (d.length_squared() - dr * dr)).clamp(0.0, 1.0)
    }

    /// The unit normal at a point p of the surface, from the contact sphere's centre.
    pub fn normal(&self, p: DVec3) -> DVec3 {
        (p - self.p0.lerp(self.p1, self.v_local(p))).normalize()
    }

    /// Mitsuba's uv at a point p of the surface: the angle around the axis, and the position
    /// along the shape's segments.
    pub fn uv(&self, p: DVec3) -> [f64; 2] {
        let a = self.axis();
        let (u_rot, u_rad) = angle_frame(a);
        let n = self.normal(p);
        let mut u = u_rot.dot(n).atan2(u_rad.dot(n));
        if u < 0.0 {
            u += TAU;
        }
        [u / TAU, (self.v_local(p) + self.index as f64) / self.count as f64]
    }

    /// The corners of its box: its end points +- their radii.
    pub fn box_corners(&self) -> [DVec3; 8] {
        let lo = (self.p0 - DVec3::splat(self.r0)).min(self.p1 - DVec3::splat(self.r1));
        let hi = (self.p0 + DVec3::splat(self.r0)).max(self.p1 + DVec3::splat(self.r1));
        std::array::from_fn(|c| DVec3::new(if c & 1 == 0 { lo.x } else { hi.x }, if c & 2 == 0 { lo.y } else { hi.y }, if c & 4 == 0 { lo.z } else { hi.z }))
    }
}

/// Mitsuba's frame for the angle around axis a: u_rot, the world's +z made orthogonal to a
/// ((0, 1, 0) where a is exactly +-z), and u_rad = u_rot x a.
pub fn angle_frame(a: DVec3) -> (DVec3, DVec3) {
    let guide = DVec3::Z;
    let u_rot = if guide.dot(a).abs() == 1.0 { DVec3::Y } else { (guide - a * a.dot(guide)).normalize() };
    (u_rot, u_rot.cross(a))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curves_are_read_with_blank_lines_between_them_and_bad_lines_named() {
        let curves = read_curves("\n0 0 0 0.1\n1 0 0 0.1\n\n\n0 1 0 0.2\n0 2 0 0.3\n0 3 0 0.3 ignored\n", 2).unwrap();
        assert_eq!(curves.len(), 2);
        assert_eq!(curves[1].len(), 3);
        let segments = segments(&curves, &DAffine3::from_scale(DVec3::splat(2.0)));
        assert_eq!(segments.len(), 3);
        assert_eq!((segments[2].index, segments[2].count), (2, 3));
        assert_eq!(segments.iter().map(|s| s.first).collect::<Vec<_>>(), [true, true, false]);
        // The points move, the radii do not.
        assert_eq!((segments[1].p0, segments[1].r0), (DVec3::new(0.0, 2.0, 0.0), 0.2));
        assert_eq!(read_curves("0 0 0 1\n1 0 0\n", 2), Err((2, "a control point is `x y z radius` (got 3 number(s): \"1 0 0\")".to_string())));
        assert!(read_curves("0 0 0 1\n\n1 1 1 1\n", 2).unwrap_err().0 == 1);
        assert!(read_curves("0 0 0 1\nx 0 0 1\n", 2).unwrap_err().0 == 2);
        assert!(read_curves("\n\n", 2).is_err());
    }

    /// A capsule of radius 1 from (0, 0, 0) to (4, 0, 0): its side, its end spheres, its
    /// back faces culled; a cone's contact parameter and normal.
    #[test]
    fn a_ray_enters_the_swept_sphere_on_its_side_and_its_caps() {
        let s = CurveSegment { p0: DVec3::ZERO, r0: 1.0, p1: DVec3::new(4.0, 0.0, 0.0), r1: 1.0, index: 0, count: 1, first: true };
        let t = s.intersect(DVec3::new(2.0, 0.0, 5.0), DVec3::NEG_Z, 0.0, f64::INFINITY).unwrap();
        assert!((t - 4.0).abs() < 1e-12);
        let p = DVec3::new(2.0, 0.0, 1.0);
        assert!((s.normal(p) - DVec3::Z).length() < 1e-12 && (s.v_local(p) - 0.5).abs() < 1e-12);
        // The end sphere at p1: entered at x = 5.
        let t = s.intersect(DVec3::new(9.0, 0.0, 0.0), DVec3::NEG_X, 0.0, f64::INFINITY).unwrap();
        assert!((t - 4.0).abs() < 1e-12 && s.v_local(DVec3::new(5.0, 0.0, 0.0)) == 1.0);
        // From inside: the exit is a back face.
        assert!(s.intersect(DVec3::new(2.0, 0.0, 0.0), DVec3::Z, 0.0, f64::INFINITY).is_none());
        assert!(s.intersect(DVec3::new(2.0, 0.0, 5.0), DVec3::NEG_Z, 0.0, 3.9).is_none());
        // A cone from radius 1 to 0.5: the contact parameter of a side point makes the normal
        // orthogonal to the side.
        let c = CurveSegment { p0: DVec3::ZERO, r0: 1.0, p1: DVec3::new(4.0, 0.0, 0.0), r1: 0.5, index: 0, count: 1, first: true };
        let t = c.intersect(DVec3::new(2.0, 0.0, 5.0), DVec3::NEG_Z, 0.0, f64::INFINITY).unwrap();
        let p = DVec3::new(2.0, 0.0, 5.0 - t);
        let v = c.v_local(p);
        let centre = c.p0.lerp(c.p1, v);
        assert!(((p - centre).length() - (1.0 - 0.5 * v)).abs() < 1e-9, "on the contact sphere");
        // The normal is orthogonal to the side's generator (from the contact point, the
        // surface runs along the tangent of both spheres).
        let n = c.normal(p);
        assert!(n.z > 0.99 && n.x > 0.0, "tilted towards the thinner end: {n:?}");
    }

    #[test]
    fn the_angle_starts_across_the_axis_and_v_runs_along_the_segments() {
        let s = CurveSegment { p0: DVec3::ZERO, r0: 1.0, p1: DVec3::new(4.0, 0.0, 0.0), r1: 1.0, index: 1, count: 4, first: false };
        // Axis +x: u_rot = +z, u_rad = z x x = +y.
        let (u_rot, u_rad) = angle_frame(DVec3::X);
        assert!((u_rot - DVec3::Z).length() < 1e-12 && (u_rad - DVec3::Y).length() < 1e-12);
        let [u, v] = s.uv(DVec3::new(1.0, 1.0, 0.0));
        assert!(u.abs() < 1e-12 && (v - 0.3125).abs() < 1e-12);
        let [u, _] = s.uv(DVec3::new(1.0, 0.0, 1.0));
        assert!((u - 0.25).abs() < 1e-12);
        assert_eq!(angle_frame(DVec3::NEG_Z).0, DVec3::Y);
    }
}
