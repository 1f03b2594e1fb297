//! A directional light (Mitsuba's `directional`): irradiance E (W/m^2, on a surface facing it)
//! arriving from one direction at infinity, a sun without extent
//! (`shaders/emitters/directional.wgsl`). A delta light: only next event estimation finds it,
//! with density 1; its shadow ray runs to infinity.

use std::f64::consts::PI;

use glam::DVec3;

use super::{environment::bounding_radius, luminance, Light};
use crate::scene::Scene;

#[derive(Debug, Clone, PartialEq)]
pub struct DirectionalLight {
    /// The unit direction the light travels in (from the light towards the scene).
    pub direction: DVec3,
    /// Irradiance per channel on a surface facing the light.
    pub irradiance: DVec3,
}

/// The directional lights, in scene order.
pub(super) fn lights(scene: &Scene) -> Vec<Light> {
    (0..scene.directional_lights.len()).map(Light::Directional).collect()
}

/// Emitted power into the scene: the irradiance times its cross-section pi r^2, r the scene's
/// bounding radius (pbrt-v4's DirectionalLight::Phi).
pub(super) fn power(scene: &Scene, i: usize) -> f64 {
    let r = bounding_radius(scene);
    PI * r * r * luminance(scene.directional_lights[i].irradiance)
}
