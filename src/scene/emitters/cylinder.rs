//! An emissive cylinder (Mitsuba's `cylinder` with an `area` emitter): a diffuse area light
//! emitting on the side of its normals (outwards, or inwards with flip_normals), or on both
//! (`shaders/emitters/cylinder.wgsl`). It is sampled as Mitsuba samples it, uniformly by area
//! (`Quadric::sample_position`). The light cylinders come first among the kernel's cylinders
//! (`gpu::features::quadric_order`).

use std::f64::consts::PI;

use super::{luminance, Light};
use crate::scene::{QuadricKind, Scene};

/// The emissive cylinders, in scene order (indices into `Scene::quadrics`).
pub(super) fn lights(scene: &Scene) -> Vec<Light> {
    scene
        .quadrics
        .iter()
        .enumerate()
        .filter(|(_, q)| q.kind == QuadricKind::Cylinder && scene.materials[q.material].is_emissive())
        .map(|(i, _)| Light::Cylinder(i))
        .collect()
}

/// Emitted power: pi times area times radiance, twice that for a two-sided emitter.
pub(super) fn power(scene: &Scene, i: usize) -> f64 {
    let q = &scene.quadrics[i];
    let sides = if q.two_sided_emission { 2.0 } else { 1.0 };
    PI * sides * q.area() * luminance(scene.materials[q.material].emission)
}
