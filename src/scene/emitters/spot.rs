//! A spot light (Mitsuba's `spot`): a point light whose intensity falls off around its axis
//! (`shaders/emitters/spot.wgsl`). As Mitsuba's `falloff_curve`: at angle theta from the axis,
//! full intensity within `beam_width`, none beyond `cutoff_angle`, and between them a linear
//! ramp in the angle, (cutoff - theta) / (cutoff - beam_width). A delta light, like `point`.
//! An optional texture projected along the cone multiplies the intensity (`SpotTexture`).

use std::f64::consts::PI;

use glam::DVec3;

use super::{luminance, Light};
use crate::scene::{Scene, Texture};

/// Mitsuba's defaults: a cutoff of 20 degrees, a beam width of three quarters of the cutoff.
pub const DEFAULT_CUTOFF_ANGLE: f64 = 20.0;
pub const BEAM_WIDTH_OF_CUTOFF: f64 = 0.75;

#[derive(Debug, Clone, PartialEq)]
pub struct SpotLight {
    pub position: DVec3,
    /// The unit direction it shines along (its local +z).
    pub direction: DVec3,
    /// Radiant intensity on the axis, W/sr per channel.
    pub intensity: DVec3,
    /// Degrees, 0 < beam_width <= cutoff_angle <= 180.
    pub cutoff_angle: f64,
    pub beam_width: f64,
    /// Mitsuba's `texture`, projected along the cone.
    pub texture: Option<SpotTexture>,
}

/// A texture projected along a spot light's cone (Mitsuba's spot `texture`): the direction d
/// from the light, in its frame (x = up x direction, y = direction x x, z = direction, as
/// Mitsuba's `lookat` makes `to_world`), is looked up at spot.cpp's `direction_to_uv`,
/// uv = 1/2 + (d_x, d_y) / (2 d_z tan(cutoff_angle)), and the value multiplies the intensity.
#[derive(Debug, Clone, PartialEq)]
pub struct SpotTexture {
    pub texture: Texture,
    /// The light frame's y axis (the texture's v runs along it), orthogonal to the direction.
    pub up: DVec3,
}

/// The frame (x, y) of a light shining along unit `direction` with `up` towards its y axis:
/// Mitsuba's `lookat` (x = normalize(up x direction), y = direction x x).
pub fn light_frame(direction: DVec3, up: DVec3) -> (DVec3, DVec3) {
    let x = up.cross(direction).normalize();
    (x, direction.cross(x))
}

impl SpotLight {
    /// The falloff at cos(theta) from the axis (Mitsuba's `falloff_curve`): 1 inside the beam,
    /// the linear ramp in angle to 0 at the cutoff, 0 beyond.
    pub fn falloff(&self, cos_theta: f64) -> f64 {
        let (cutoff, beam) = (self.cutoff_angle.to_radians(), self.beam_width.to_radians());
        if cos_theta <= cutoff.cos() {
            0.0
        } else if cos_theta >= beam.cos() {
            1.0
        } else {
            (cutoff - cos_theta.clamp(-1.0, 1.0).acos()) / (cutoff - beam)
        }
    }

    /// Emitted power: 2 pi I times the falloff integrated over the sphere,
    /// int_0^cutoff falloff(theta) sin(theta) dtheta = 1 - (sin(cutoff) - sin(beam)) / (cutoff - beam)
    /// (1 - cos(beam) where they meet).
    pub fn power(&self) -> f64 {
        let (cutoff, beam) = (self.cutoff_angle.to_radians(), self.beam_width.to_radians());
        let profile = if cutoff - beam > 1e-9 { 1.0 - (cutoff.sin() - beam.sin()) / (cutoff - beam) } else { 1.0 - beam.cos() };
        // A texture scales it by its mean (the light-selection weight: an estimate, as the
        // texture's texels do not cover equal solid angles).
        let texture = self.texture.as_ref().map_or(1.0, |t| luminance(t.texture.mean()));
        2.0 * PI * luminance(self.intensity) * profile * texture
    }
}

/// The spot lights, in scene order.
pub(super) fn lights(scene: &Scene) -> Vec<Light> {
    (0..scene.spot_lights.len()).map(Light::Spot).collect()
}

pub(super) fn power(scene: &Scene, i: usize) -> f64 {
    scene.spot_lights[i].power()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed-form power is 2 pi I times the falloff integrated over the sphere, checked by
    /// a midpoint sum of `falloff` (the profile the kernel evaluates) in theta.
    #[test]
    fn power_integrates_the_falloff() {
        for (cutoff, beam) in [(20.0, 15.0), (30.0, 15.0), (60.0, 5.0), (45.0, 45.0), (170.0, 90.0)] {
            let spot = SpotLight { position: DVec3::ZERO, direction: DVec3::Z, intensity: DVec3::ONE, cutoff_angle: cutoff, beam_width: beam, texture: None };
            let n = 200_000;
            let dt = PI / n as f64;
            let sum: f64 = (0..n).map(|i| (i as f64 + 0.5) * dt).map(|t| spot.falloff(t.cos()) * t.sin() * dt).sum();
            let expected = 2.0 * PI * luminance(spot.intensity) * sum;
            assert!((spot.power() - expected).abs() < 1e-6 * expected, "cutoff {cutoff}, beam {beam}: {} against {expected}", spot.power());
        }
    }
}
