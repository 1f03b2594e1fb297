//! The watertight ray-triangle test of Woop, Benthin and Wald (2013, "Watertight Ray/Triangle
//! Intersection", JCGT 2(1)): the ray is sheared so that it runs along +z from the origin, the
//! triangle's vertices are transformed the same way, and the three 2D edge functions decide
//! the hit. A point on a shared edge or vertex gets the same edge function values in both
//! triangles (they are computed from the same transformed vertices, in f64 when an f32 result
//! is 0), so a ray through it hits one of them: none slips between. This is the CPU twin of the
//! kernel's test, and the reference the BVH's traversal is checked against.

use glam::Vec3;

/// A ray prepared for the watertight test: the dominant axis `kz`, the two others, and the
/// shear constants.
#[derive(Debug, Clone, Copy)]
pub struct ShearedRay {
    pub origin: Vec3,
    kx: usize,
    ky: usize,
    kz: usize,
    sx: f32,
    sy: f32,
    sz: f32,
}

impl ShearedRay {
    /// Prepares a ray of `direction` (not necessarily normalised, not zero) from `origin`.
    pub fn new(origin: Vec3, direction: Vec3) -> ShearedRay {
        let a = direction.abs();
        // The axis of the largest component becomes z; x and y follow it cyclically, swapped
        // when that component is negative, which keeps the triangle's winding.
        let kz = if a.x > a.y { if a.x > a.z { 0 } else { 2 } } else if a.y > a.z { 1 } else { 2 };
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        if direction[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let d = direction;
        ShearedRay { origin, kx, ky, kz, sx: d[kx] / d[kz], sy: d[ky] / d[kz], sz: 1.0 / d[kz] }
    }

    /// The distance along the ray (in units of the direction's length) to triangle (a, b, c),
    /// when the ray hits it at a distance in (0, t_max), with the barycentrics of b and c.
    pub fn hit(&self, a: Vec3, b: Vec3, c: Vec3, t_max: f32) -> Option<(f32, f32, f32)> {
        let (kx, ky, kz) = (self.kx, self.ky, self.kz);
        let (a, b, c) = (a - self.origin, b - self.origin, c - self.origin);
        // Shear and scale the vertices into the ray's space.
        let ax = a[kx] - self.sx * a[kz];
        let ay = a[ky] - self.sy * a[kz];
        let bx = b[kx] - self.sx * b[kz];
        let by = b[ky] - self.sy * b[kz];
        let cx = c[kx] - self.sx * c[kz];
        let cy = c[ky] - self.sy * c[kz];
        // Scaled barycentrics: the 2D edge functions.
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        // Exactly zero in f32: decide in f64, so that the edge shared by two triangles gets
        // one verdict in both.
        if u == 0.0 || v == 0.0 || w == 0.0 {
            let (ax, ay, bx, by, cx, cy) = (ax as f64, ay as f64, bx as f64, by as f64, cx as f64, cy as f64);
            u = (cx * by - cy * bx) as f32;
            v = (ax * cy - ay * cx) as f32;
            w = (bx * ay - by * ax) as f32;
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        // The hit's distance, scaled by det: compared without a division.
        let (az, bz, cz) = (self.sz * a[kz], self.sz * b[kz], self.sz * c[kz]);
        let t = u * az + v * bz + w * cz;
        if (det > 0.0 && (t <= 0.0 || t >= t_max * det)) || (det < 0.0 && (t >= 0.0 || t <= t_max * det)) {
            return None;
        }
        let inv = 1.0 / det;
        Some((t * inv, v * inv, w * inv))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_inside_misses_outside_both_windings() {
        let (a, b, c) = (Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 1.0));
        let ray = ShearedRay::new(Vec3::new(0.25, 0.25, 0.0), Vec3::Z);
        let (t, bu, bv) = ray.hit(a, b, c, f32::INFINITY).expect("hit");
        assert!((t - 1.0).abs() < 1e-6 && (bu - 0.25).abs() < 1e-6 && (bv - 0.25).abs() < 1e-6);
        assert!(ray.hit(a, c, b, f32::INFINITY).is_some(), "the test is two-sided");
        assert!(ray.hit(a, b, c, 0.5).is_none(), "beyond t_max");
        let behind = ShearedRay::new(Vec3::new(0.25, 0.25, 2.0), Vec3::Z);
        assert!(behind.hit(a, b, c, f32::INFINITY).is_none());
        let outside = ShearedRay::new(Vec3::new(0.75, 0.75, 0.0), Vec3::Z);
        assert!(outside.hit(a, b, c, f32::INFINITY).is_none());
    }
}
