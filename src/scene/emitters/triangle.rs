//! An emissive mesh triangle: a diffuse area light, emitting on the side of its winding normal
//! or on both (`shaders/emitters/triangle.wgsl`).

use super::Light;
use crate::scene::Scene;

/// Every triangle of every emissive mesh, mesh by mesh, triangle by triangle.
pub(super) fn lights(scene: &Scene) -> Vec<Light> {
    scene
        .meshes
        .iter()
        .enumerate()
        .filter(|(_, m)| scene.materials[m.material].is_emissive())
        .flat_map(|(mesh, m)| (0..m.triangles.len()).map(move |triangle| Light::Triangle { mesh, triangle }))
        .collect()
}

/// How many `lights` lists, counted without listing them.
pub(super) fn count(scene: &Scene) -> usize {
    scene.meshes.iter().filter(|m| scene.materials[m.material].is_emissive()).map(|m| m.triangles.len()).sum()
}

/// Emitted power: pi times area times radiance, twice that for a two-sided emitter.
pub(super) fn power(scene: &Scene, mesh: usize, triangle: usize) -> f64 {
    let m = &scene.meshes[mesh];
    super::area_emitter_power(m.triangle_area(triangle), scene.materials[m.material].emission, m.two_sided_emission)
}
