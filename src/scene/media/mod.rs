//! Participating media: Mitsuba 3's `homogeneous` medium (`src/media/homogeneous.cpp`) with its
//! `isotropic` and `hg` phase functions (`src/phase/`), pbrt-v4's `HomogeneousMedium`.
//!
//! A medium fills the space a surface's material bounds (`Material::interior`, on the side its
//! normal points away from; `Material::exterior`, on the other), or the space the camera sits in
//! (`Scene::camera_medium`), as pbrt-v4's `MediumInterface` does: a graphics-state attribute
//! beside the material. A ray keeps its medium across surfaces that mark no medium boundary.
//! The kernel's side is `shaders/medium.wgsl` (free-flight sampling, transmittance) and
//! `shaders/phase.wgsl`.

use glam::DVec3;

use super::hash::{real, vec3};

/// At most this many media: a material's flags hold its interior's and exterior's indices in 8
/// bits each, `NO_MEDIUM` (255) for none.
pub const MAX_MEDIA: usize = 255;

/// Floats per medium record in the kernel's data table (`Medium::pack`).
pub const MEDIUM_RECORD_FLOATS: usize = 8;

/// The most surfaces one shadow ray of the volumetric path tracer passes through (null surfaces,
/// masks, media boundaries); a light behind more counts as shadowed (shaders/volpath.wgsl).
pub const MAX_SHADOW_CROSSINGS: u32 = 8;

/// Null interactions a path may have beyond one per scattering event: it traces at most
/// `max_segments(max_depth)` segments (shaders/volpath.wgsl).
pub const EXTRA_NULL_SEGMENTS: u32 = 8;

/// The most segments one path of the volumetric path tracer traces at `max_depth`.
pub fn max_segments(max_depth: u32) -> u32 {
    2 * max_depth + EXTRA_NULL_SEGMENTS
}

/// The phase function: how a scattering event redistributes light over directions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Phase {
    /// 1 / 4π in every direction (Mitsuba's `isotropic`).
    Isotropic,
    /// Henyey and Greenstein's lobe of mean cosine `g` in (-1, 1) between the direction light
    /// travelled and the direction it leaves in: g > 0 scatters forward (Mitsuba's `hg`).
    HenyeyGreenstein { g: f64 },
}

impl Phase {
    /// The mean cosine (0 for isotropic scattering, which the kernel runs as HG with g = 0).
    pub fn g(&self) -> f64 {
        match self {
            Phase::Isotropic => 0.0,
            Phase::HenyeyGreenstein { g } => *g,
        }
    }
}

/// A homogeneous medium: extinction and single-scattering albedo per RGB channel, constant in
/// space.
#[derive(Debug, Clone, PartialEq)]
pub struct Medium {
    pub name: String,
    /// Extinction coefficient σ_t (per unit length), Mitsuba's `sigma_t` times its `scale`.
    pub sigma_t: DVec3,
    /// Single-scattering albedo σ_s / σ_t, in [0, 1].
    pub albedo: DVec3,
    pub phase: Phase,
}

impl Medium {
    /// Scattering coefficient σ_s = albedo σ_t.
    pub fn sigma_s(&self) -> DVec3 {
        self.albedo * self.sigma_t
    }

    /// The kernel's record (`medium_at` in shaders/medium.wgsl): σ_t and the phase's g, then σ_s
    /// and 0.
    pub fn pack(&self) -> [f32; MEDIUM_RECORD_FLOATS] {
        let (t, s) = (self.sigma_t.as_vec3(), self.sigma_s().as_vec3());
        [t.x, t.y, t.z, self.phase.g() as f32, s.x, s.y, s.z, 0.0]
    }

    pub fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        line("sigma_t", vec3(self.sigma_t));
        line("albedo", vec3(self.albedo));
        line("g", real(self.phase.g()));
    }
}

/// The exact transmittance exp(-σ_t d) of a homogeneous medium over a distance d (for tests and
/// analytic references).
pub fn transmittance(sigma_t: DVec3, distance: f64) -> DVec3 {
    DVec3::new((-sigma_t.x * distance).exp(), (-sigma_t.y * distance).exp(), (-sigma_t.z * distance).exp())
}

/// Henyey-Greenstein's density over the sphere of directions, per steradian, at the cosine
/// `cos_theta` between the direction light travelled and the one it leaves in:
/// (1 - g²) / (4π (1 + g² - 2 g cos θ)^{3/2}).
pub fn henyey_greenstein(g: f64, cos_theta: f64) -> f64 {
    let denom = 1.0 + g * g - 2.0 * g * cos_theta;
    (1.0 - g * g) / (4.0 * std::f64::consts::PI * denom * denom.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The phase function integrates to 1 over the sphere (midpoint rule in cos θ), for
    /// isotropic and strongly peaked lobes alike.
    #[test]
    fn henyey_greenstein_is_normalised() {
        for g in [-0.9, -0.3, 0.0, 0.5, 0.9] {
            let n = 200_000;
            let sum: f64 = (0..n).map(|i| henyey_greenstein(g, -1.0 + 2.0 * (i as f64 + 0.5) / n as f64)).sum();
            let integral = sum * 2.0 / n as f64 * 2.0 * std::f64::consts::PI;
            assert!((integral - 1.0).abs() < 1e-6, "g = {g}: {integral}");
        }
    }
}
