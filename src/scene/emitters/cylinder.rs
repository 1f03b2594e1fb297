//! An emissive cylinder (Mitsuba's `cylinder` with an `area` emitter): a diffuse area light
//! emitting on the side of its normals (outwards, or inwards with flip_normals), or on both
//! (`shaders/emitters/cylinder.wgsl`). It is sampled as Mitsuba samples it, uniformly by area
//! (`Quadric::sample_position`). The light cylinders come first among the kernel's cylinders
//! (`gpu::features::quadric_order`).

use super::{area_emitter_power, emissive_quadrics, Light};
use crate::scene::{QuadricKind, Scene};

/// The emissive cylinders, in scene order (indices into `Scene::quadrics`).
pub(super) fn lights(scene: &Scene) -> Vec<Light> {
    emissive_quadrics(scene, QuadricKind::Cylinder, Light::Cylinder)
}

/// Emitted power: pi times area times radiance, twice that for a two-sided emitter.
pub(super) fn power(scene: &Scene, i: usize) -> f64 {
    let q = &scene.quadrics[i];
    area_emitter_power(q.area(), scene.materials[q.material].emission, q.two_sided_emission)
}
