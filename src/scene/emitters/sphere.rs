//! An emissive sphere: a diffuse area light emitting outwards (`shaders/emitters/sphere.wgsl`).
//! The light spheres come first among the kernel's spheres, so sphere light l is kernel
//! sphere l (`gpu::features::sphere_order`).

use std::f64::consts::PI;

use super::{luminance, Light};
use crate::scene::Scene;

/// The emissive spheres, in scene order.
pub(super) fn lights(scene: &Scene) -> Vec<Light> {
    scene.light_spheres().into_iter().map(Light::Sphere).collect()
}

/// Emitted power: pi times the area 4 pi r^2 times the radiance.
pub(super) fn power(scene: &Scene, i: usize) -> f64 {
    let s = &scene.spheres[i];
    PI * 4.0 * PI * s.radius * s.radius * luminance(scene.materials[s.material].emission)
}
