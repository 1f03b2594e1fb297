//! A projector (Mitsuba's `projector`, src/emitters/projector.cpp): a pinhole that projects an
//! irradiance image into the scene, the perspective camera run backwards
//! (`shaders/emitters/projector.wgsl`). A delta light, like `point`.
//!
//! Mitsuba's radiometry: a point x at distance d, seen from the pinhole at angle theta from the
//! axis, lies on the ray through the image point uv of the virtual image plane at distance 1
//! (the perspective sensor's mapping, its field of view resolved at the texture's aspect
//! ratio); it receives E(uv) pi scale / (z^2 cos(theta)) with z = d cos(theta) the depth along
//! the axis, so that a constant image lights a plane facing the projector at depth z with the
//! constant irradiance E pi scale / z^2 across it. As an intensity (radiance times d^2):
//! I = E(uv) pi scale / cos^3(theta) inside the image's frustum, 0 outside.

use std::f64::consts::PI;

use glam::DVec3;

use super::{luminance, Light};
use crate::scene::{Fov, Scene, Texture};

#[derive(Debug, Clone, PartialEq)]
pub struct ProjectorLight {
    pub position: DVec3,
    /// The unit axis it projects along (its frame's z).
    pub direction: DVec3,
    /// The frame's unit y axis (the image's up), orthogonal to `direction`.
    pub up: DVec3,
    /// The field of view by Mitsuba's rule, resolved at the irradiance texture's resolution.
    pub fov: Fov,
    /// Mitsuba's `irradiance` (a colour is a `rawconstant` texture: one value, a 1 x 1 image).
    pub irradiance: Texture,
    /// Mitsuba's `scale`, times `to_world`'s scale s (Mitsuba divides by the local depth
    /// squared, (z / s)^2, and by its unnormalised axis's dot product with the direction,
    /// s cos(theta)).
    pub scale: f64,
}

impl ProjectorLight {
    /// The irradiance image's resolution, which its aspect ratio and field of view follow
    /// (Mitsuba's `Texture::resolution`: a bitmap's size, 1 x 1 for any other texture).
    pub fn resolution(&self) -> (u32, u32) {
        match &self.irradiance {
            Texture::Bitmap(b) => (b.image.width, b.image.height),
            _ => (1, 1),
        }
    }

    /// tan of the half field of view along the image's x and y.
    pub fn half_extents(&self) -> (f64, f64) {
        let (w, h) = self.resolution();
        self.fov.half_extents(w, h)
    }

    /// The image point uv of a direction `d_local` in the light's frame (x = up x direction,
    /// y = up, z = direction: Mitsuba's camera space, x to the left), as the perspective
    /// projection maps it: u = 1/2 - x / (2 z tan_x), v = 1/2 - y / (2 z tan_y); the uv scale
    /// (-1 / (2 tan_x), -1 / (2 tan_y)).
    pub fn uv_scale(&self) -> (f64, f64) {
        let (tx, ty) = self.half_extents();
        (-0.5 / tx, -0.5 / ty)
    }

    /// Emitted power: I integrated over the frustum. With domega = cos^3(theta) dA on the
    /// image plane at distance 1, it is pi scale times E integrated over the image rectangle,
    /// (2 tan_x)(2 tan_y) times E's mean (Mitsuba's `m_sensor_area`).
    pub fn power(&self) -> f64 {
        let (tx, ty) = self.half_extents();
        PI * self.scale * luminance(self.irradiance.mean()) * 4.0 * tx * ty
    }
}

/// The projectors, in scene order.
pub(super) fn lights(scene: &Scene) -> Vec<Light> {
    (0..scene.projector_lights.len()).map(Light::Projector).collect()
}

pub(super) fn power(scene: &Scene, i: usize) -> f64 {
    scene.projector_lights[i].power()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed-form power is I integrated over the frustum, checked by a midpoint sum over
    /// directions (the kernel's intensity E pi scale / cos^3 inside the image, 0 outside).
    #[test]
    fn power_integrates_the_intensity_over_the_frustum() {
        let light = ProjectorLight {
            position: DVec3::ZERO,
            direction: DVec3::Z,
            up: DVec3::Y,
            fov: Fov::X(50.0),
            irradiance: Texture::RawConstant { value: DVec3::new(2.0, 1.0, 0.5) },
            scale: 3.0,
        };
        let (tx, ty) = light.half_extents();
        let i = PI * light.scale * luminance(DVec3::new(2.0, 1.0, 0.5));
        // Over the hemisphere in (theta, phi): I / cos^3 where the direction projects inside.
        let (n_t, n_p) = (2000, 2000);
        let mut sum = 0.0;
        for a in 0..n_t {
            let theta = (a as f64 + 0.5) / n_t as f64 * PI / 2.0;
            for b in 0..n_p {
                let phi = (b as f64 + 0.5) / n_p as f64 * 2.0 * PI;
                let d = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
                if (d.x / d.z).abs() <= tx && (d.y / d.z).abs() <= ty {
                    sum += i / d.z.powi(3) * theta.sin() * (PI / 2.0 / n_t as f64) * (2.0 * PI / n_p as f64);
                }
            }
        }
        assert!((light.power() - sum).abs() < 2e-3 * sum, "{} against {sum}", light.power());
    }
}
