//! A point light (Mitsuba's `point`): intensity I (W/sr) from one point, equal in every
//! direction (`shaders/emitters/point.wgsl`). A delta light: only next event estimation finds it,
//! with density 1 and the radiance I / d^2 of a point at distance d.

use std::f64::consts::PI;

use glam::DVec3;

use super::{luminance, Light};
use crate::scene::Scene;

#[derive(Debug, Clone, PartialEq)]
pub struct PointLight {
    pub position: DVec3,
    /// Radiant intensity, W/sr per channel.
    pub intensity: DVec3,
}

/// The point lights, in scene order.
pub(super) fn lights(scene: &Scene) -> Vec<Light> {
    (0..scene.point_lights.len()).map(Light::Point).collect()
}

/// Emitted power: 4 pi times the intensity (pbrt-v4's PointLight::Phi).
pub(super) fn power(scene: &Scene, i: usize) -> f64 {
    4.0 * PI * luminance(scene.point_lights[i].intensity)
}
