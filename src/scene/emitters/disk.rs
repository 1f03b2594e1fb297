//! An emissive disk (Mitsuba's `disk` with an `area` emitter): a diffuse area light emitting on
//! the side of its normal, or on both (`shaders/emitters/disk.wgsl`). It is sampled as Mitsuba
//! samples it, uniformly by area (`Quadric::sample_position`). The light disks come first among
//! the kernel's quadrics, so disk light l is kernel quadric l (`gpu::features::quadric_order`).

use super::{area_emitter_power, emissive_quadrics, Light};
use crate::scene::{QuadricKind, Scene};

/// The emissive disks, in scene order (indices into `Scene::quadrics`).
pub(super) fn lights(scene: &Scene) -> Vec<Light> {
    emissive_quadrics(scene, QuadricKind::Disk, Light::Disk)
}

/// Emitted power: pi times area times radiance, twice that for a two-sided emitter.
pub(super) fn power(scene: &Scene, i: usize) -> f64 {
    let q = &scene.quadrics[i];
    area_emitter_power(q.area(), scene.materials[q.material].emission, q.two_sided_emission)
}
