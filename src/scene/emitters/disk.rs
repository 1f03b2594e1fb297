//! An emissive disk (Mitsuba's `disk` with an `area` emitter): a diffuse area light emitting on
//! the side of its normal, or on both (`shaders/emitters/disk.wgsl`). It is sampled as Mitsuba
//! samples it, uniformly by area (`Quadric::sample_position`). The light disks come first among
//! the kernel's quadrics, so disk light l is kernel quadric l (`gpu::features::quadric_order`).

use std::f64::consts::PI;

use super::{luminance, Light};
use crate::scene::{QuadricKind, Scene};

/// The emissive disks, in scene order (indices into `Scene::quadrics`).
pub(super) fn lights(scene: &Scene) -> Vec<Light> {
    scene
        .quadrics
        .iter()
        .enumerate()
        .filter(|(_, q)| q.kind == QuadricKind::Disk && scene.materials[q.material].is_emissive())
        .map(|(i, _)| Light::Disk(i))
        .collect()
}

/// Emitted power: pi times area times radiance, twice that for a two-sided emitter.
pub(super) fn power(scene: &Scene, i: usize) -> f64 {
    let q = &scene.quadrics[i];
    let sides = if q.two_sided_emission { 2.0 } else { 1.0 };
    PI * sides * q.area() * luminance(scene.materials[q.material].emission)
}
