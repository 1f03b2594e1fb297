//! Mitsuba's `disk` (`src/shapes/disk.cpp`): the unit disk x^2 + y^2 <= 1 at z = 0 of object
//! space, its normal +z (`shaders/quadrics/disk.wgsl` is the kernel's).

use std::f64::consts::{PI, TAU};

use glam::DVec3;

use super::Quadric;

/// World area: pi |dp/du x dp/dv| of the ellipse the affine map makes of the unit disk
/// (Mitsuba's pi du h, h the height of the ellipse's parallelogram).
pub(super) fn area(q: &Quadric) -> f64 {
    PI * q.to_world.matrix3.x_axis.cross(q.to_world.matrix3.y_axis).length()
}

/// Object-space ray (o, d): its crossing of z = 0 where within the unit disk and (t_min, t_max).
pub(super) fn intersect(o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<f64> {
    let t = -o.z / d.z;
    let p = o + d * t;
    (t > t_min && t < t_max && p.x * p.x + p.y * p.y <= 1.0).then_some(t)
}

/// Mitsuba's uv of the disk at object point `local`: (r, phi / 2 pi), phi in [0, 2 pi).
pub(super) fn uv(local: DVec3) -> [f64; 2] {
    let r = (local.x * local.x + local.y * local.y).sqrt();
    let v = local.y.atan2(local.x) / TAU;
    [r, if v < 0.0 { v + 1.0 } else { v }]
}

/// Shirley and Chiu's concentric map of the square onto the unit disk (Mitsuba's
/// `warp::square_to_uniform_disk_concentric`), at z = 0.
pub(super) fn sample_local(u: [f64; 2]) -> DVec3 {
    let (r1, r2) = (2.0 * u[0] - 1.0, 2.0 * u[1] - 1.0);
    if r1 == 0.0 && r2 == 0.0 {
        return DVec3::ZERO;
    }
    let (r, phi) = if r1.abs() < r2.abs() { (r2, 0.5 * PI - 0.25 * PI * r1 / r2) } else { (r1, 0.25 * PI * r2 / r1) };
    DVec3::new(r * phi.cos(), r * phi.sin(), 0.0)
}
