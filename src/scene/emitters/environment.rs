//! The constant environment (Mitsuba's `constant` emitter): radiance `render.environment` from
//! every direction at infinity (`shaders/emitters/environment.wgsl`). Next event estimation
//! samples it only where the method asks (`Method::environment`); otherwise escaped rays
//! alone find it, as before it was a light.

use std::f64::consts::PI;

use glam::DVec3;

use super::{luminance, Light};
use crate::scene::Scene;

/// The environment, where it is not black.
pub(super) fn lights(scene: &Scene) -> Vec<Light> {
    if scene.has_environment() { vec![Light::Environment] } else { Vec::new() }
}

/// Emitted power of a constant environment seen by a scene of bounding radius r, as pbrt-v4's
/// UniformInfiniteLight::Phi: 4 pi (over directions) times pi r^2 (the scene's cross-section)
/// times the radiance.
pub(super) fn power(scene: &Scene) -> f64 {
    let r = bounding_radius(scene);
    4.0 * PI * PI * r * r * luminance(scene.render.environment)
}

/// Radius of a sphere around the scene's bounded objects (spheres, mesh vertices) and its
/// camera, centred on their bounding box; planes are unbounded and left out.
fn bounding_radius(scene: &Scene) -> f64 {
    let mut lo = scene.camera.position;
    let mut hi = scene.camera.position;
    for s in &scene.spheres {
        lo = lo.min(s.center - DVec3::splat(s.radius));
        hi = hi.max(s.center + DVec3::splat(s.radius));
    }
    for v in scene.meshes.iter().flat_map(|m| m.positions.iter()) {
        lo = lo.min(*v);
        hi = hi.max(*v);
    }
    (0.5 * (hi - lo).length()).max(1e-3)
}
