//! Mitsuba's `cylinder` (`src/shapes/cylinder.cpp`): the open unit cylinder x^2 + y^2 = 1,
//! 0 <= z <= 1, of object space, without end caps, its normals outwards
//! (`shaders/quadrics/cylinder.wgsl` is the kernel's).

use std::f64::consts::TAU;

use glam::DVec3;

use super::{solve_quadratic, Quadric};

/// Mitsuba's area: 2 pi r l with r = |to_world x| and l = |to_world z| (exact for the
/// rotations, uniform scales in x and y and translations Mitsuba allows).
pub(super) fn area(q: &Quadric) -> f64 {
    TAU * q.to_world.matrix3.x_axis.length() * q.to_world.matrix3.z_axis.length()
}

/// Object-space ray (o, d): the nearer root of (ox + t dx)^2 + (oy + t dy)^2 = 1 in (t_min, t_max)
/// whose point lies between z = 0 and z = 1, else the farther one (Mitsuba's test).
pub(super) fn intersect(o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<f64> {
    let a = d.x * d.x + d.y * d.y;
    let b = 2.0 * (d.x * o.x + d.y * o.y);
    let c = o.x * o.x + o.y * o.y - 1.0;
    let (near, far) = solve_quadratic(a, b, c)?;
    let within = |t: f64| {
        let z = o.z + d.z * t;
        t > t_min && t < t_max && (0.0..=1.0).contains(&z)
    };
    if within(near) {
        Some(near)
    } else if within(far) {
        Some(far)
    } else {
        None
    }
}

/// Mitsuba's uv of the cylinder at object point `local`: (phi / 2 pi, z), phi in [0, 2 pi).
pub(super) fn uv(local: DVec3) -> [f64; 2] {
    let phi = local.y.atan2(local.x);
    [if phi < 0.0 { phi + TAU } else { phi } / TAU, local.z]
}

/// Mitsuba's `sample_position` in object space: (cos 2 pi u1, sin 2 pi u1, u0).
pub(super) fn sample_local(u: [f64; 2]) -> DVec3 {
    let phi = TAU * u[1];
    DVec3::new(phi.cos(), phi.sin(), u[0])
}
