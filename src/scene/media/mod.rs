//! Participating media: Mitsuba 3's `homogeneous` and `heterogeneous` media
//! (`src/media/homogeneous.cpp`, `heterogeneous.cpp`) with their `isotropic` and `hg` phase
//! functions (`src/phase/`): pbrt-v4's `HomogeneousMedium` and, for a grid of extinction,
//! its `GridMedium` with one majorant.
//!
//! A medium fills the space a surface's material bounds (`Material::interior`, on the side its
//! normal points away from; `Material::exterior`, on the other), or the space the camera sits in
//! (`Scene::camera_medium`), as pbrt-v4's `MediumInterface` does: a graphics-state attribute
//! beside the material. A ray keeps its medium across surfaces that mark no medium boundary.
//! The kernel's side is `shaders/medium.wgsl` (free-flight sampling, transmittance) and
//! `shaders/phase.wgsl`.
//!
//! A heterogeneous medium's extinction σ_t(p) = scale × sigma_t(p) varies in space, a grid
//! volume's (`textures::GridVolume`) or a constant, and fills only that volume's box (Mitsuba's
//! `intersect_aabb`: outside it the medium is empty). The kernel samples it by delta tracking
//! against one majorant, scale × the largest value of the grid (Mitsuba's `m_max_density`),
//! and estimates shadow rays' transmittance by ratio tracking, as Mitsuba's volpath does. Both
//! medium kinds take an albedo that may be a grid.

use glam::{DMat4, DVec3};

use super::bsdf_data::BsdfData;
use super::hash::{real, vec3};
use super::textures::GridVolume;
use super::Texture;

/// At most this many media: a material's flags hold its interior's and exterior's indices in 8
/// bits each, `NO_MEDIUM` (255) for none.
pub const MAX_MEDIA: usize = 255;

/// Floats per medium record in the kernel's data table (`Medium::pack`).
pub const MEDIUM_RECORD_FLOATS: usize = 20;

/// The probability, per tracked segment, that delta or ratio tracking meets more null collisions
/// than the kernel's bound (`max_null_collisions`), where the path (or shadow ray) is
/// cut: the only bias of the tracking, below any measurable level.
pub const NULL_COLLISION_TAIL: f64 = 1e-15;

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

/// How one of a medium's coefficients varies in space: Mitsuba's `constvolume` (or a plain value)
/// or `gridvolume`.
#[derive(Debug, Clone, PartialEq)]
pub enum Field {
    Constant(DVec3),
    Grid(GridVolume),
}

impl Field {
    /// Its largest value over space and channels (Mitsuba's `Volume::max`: a grid's largest
    /// cell).
    pub fn max(&self) -> f64 {
        match self {
            Field::Constant(c) => c.max_element(),
            Field::Grid(g) => g.data.iter().fold(0.0f32, |m, &v| m.max(v)) as f64,
        }
    }

    /// Its mean over its cells (a constant's value).
    pub fn mean(&self) -> DVec3 {
        match self {
            Field::Constant(c) => *c,
            Field::Grid(g) => DVec3::from_array(g.mean()),
        }
    }

    pub fn constant(&self) -> Option<DVec3> {
        match self {
            Field::Constant(c) => Some(*c),
            Field::Grid(_) => None,
        }
    }

    /// The grid as a texture (for hashing, describing and packing).
    pub fn texture(&self) -> Option<Texture> {
        match self {
            Field::Constant(_) => None,
            Field::Grid(g) => Some(Texture::Volume(g.clone())),
        }
    }

    /// Its kernel slot: the value itself, or -(start + 1) of the grid's record, packed now.
    fn pack(&self, data: &mut BsdfData) -> [f32; 3] {
        match self {
            Field::Constant(c) => c.as_vec3().to_array(),
            Field::Grid(g) => [-(g.pack(data) as f32) - 1.0, 0.0, 0.0],
        }
    }
}

/// Mitsuba's medium plugins.
#[derive(Debug, Clone, PartialEq)]
pub enum MediumKind {
    /// σ_t constant everywhere: free flights sampled in closed form.
    Homogeneous,
    /// σ_t varying inside `bounds` (the sigma_t volume's box, min and max corners), nothing
    /// outside: free flights by delta tracking.
    Heterogeneous { bounds: [DVec3; 2] },
}

/// A medium: extinction and single-scattering albedo per RGB channel, and its phase function.
#[derive(Debug, Clone, PartialEq)]
pub struct Medium {
    pub name: String,
    pub kind: MediumKind,
    /// Extinction coefficient σ_t per unit length, before `scale` (a homogeneous medium's is a
    /// constant).
    pub sigma_t: Field,
    /// Mitsuba's `scale` of σ_t.
    pub scale: f64,
    /// Single-scattering albedo σ_s / σ_t, in [0, 1].
    pub albedo: Field,
    pub phase: Phase,
}

impl Medium {
    /// A homogeneous medium of constant σ_t and albedo.
    pub fn homogeneous(name: &str, sigma_t: DVec3, albedo: DVec3, phase: Phase) -> Medium {
        Medium { name: name.to_string(), kind: MediumKind::Homogeneous, sigma_t: Field::Constant(sigma_t), scale: 1.0, albedo: Field::Constant(albedo), phase }
    }

    /// Its σ_t (times scale) where constant in space.
    pub fn constant_sigma_t(&self) -> Option<DVec3> {
        self.sigma_t.constant().map(|c| c * self.scale)
    }

    /// Scattering coefficient σ_s = albedo σ_t where both are constant.
    pub fn constant_sigma_s(&self) -> Option<DVec3> {
        Some(self.albedo.constant()? * self.constant_sigma_t()?)
    }

    pub fn is_heterogeneous(&self) -> bool {
        matches!(self.kind, MediumKind::Heterogeneous { .. })
    }

    /// Its grids (sigma_t's, then albedo's).
    pub fn textures(&self) -> Vec<Texture> {
        self.sigma_t.texture().into_iter().chain(self.albedo.texture()).collect()
    }

    /// The majorant of a heterogeneous medium: scale × the largest σ_t over space and channels
    /// (Mitsuba's `m_max_density`, one number for all channels).
    pub fn majorant(&self) -> f64 {
        self.scale * self.sigma_t.max()
    }

    /// The mean number of tentative collisions against its majorant m along a line through its
    /// box, at most λ = m × the box's diagonal (0 for a homogeneous medium).
    pub fn collision_mean_bound(&self) -> f64 {
        let MediumKind::Heterogeneous { bounds: [lo, hi] } = self.kind else { return 0.0 };
        self.majorant() * (hi - lo).length()
    }

    /// The kernel's record (`medium_at` in shaders/medium.wgsl), its grids packed into `data`
    /// first: the σ_t slot (a homogeneous medium's σ_t times scale), g; the albedo slot, scale;
    /// a homogeneous medium's constant σ_s (else 0), the majorant (0: homogeneous); the box's
    /// min, 0; its max, 0.
    pub fn pack(&self, data: &mut BsdfData) -> [f32; MEDIUM_RECORD_FLOATS] {
        let (sigma_t, scale) = match (&self.kind, self.constant_sigma_t()) {
            (MediumKind::Homogeneous, Some(s)) => (s.as_vec3().to_array(), 1.0),
            _ => (self.sigma_t.pack(data), self.scale as f32),
        };
        let albedo = self.albedo.pack(data);
        let sigma_s = match self.kind {
            MediumKind::Homogeneous => self.constant_sigma_s().unwrap_or(DVec3::ZERO).as_vec3().to_array(),
            MediumKind::Heterogeneous { .. } => [0.0; 3],
        };
        let (majorant, [lo, hi]) = match self.kind {
            MediumKind::Homogeneous => (0.0, [DVec3::ZERO; 2]),
            MediumKind::Heterogeneous { bounds } => (self.majorant() as f32, bounds),
        };
        let (lo, hi) = (lo.as_vec3(), hi.as_vec3());
        [
            sigma_t[0], sigma_t[1], sigma_t[2], self.phase.g() as f32,
            albedo[0], albedo[1], albedo[2], scale,
            sigma_s[0], sigma_s[1], sigma_s[2], majorant,
            lo.x, lo.y, lo.z, 0.0,
            hi.x, hi.y, hi.z, 0.0,
        ]
    }

    /// What `pathlab check` says of it: its kind, coefficients and, for a heterogeneous medium,
    /// its box, majorant and tracking bound.
    pub fn describe(&self) -> String {
        let field = |f: &Field| match f {
            Field::Constant(c) => format!("{:?}", c.to_array()),
            Field::Grid(g) => Texture::Volume(g.clone()).describe(),
        };
        match self.kind {
            MediumKind::Homogeneous => format!(
                "homogeneous, sigma_t {} per unit length, albedo {}",
                field(&Field::Constant(self.constant_sigma_t().unwrap_or_default())),
                field(&self.albedo)
            ),
            MediumKind::Heterogeneous { bounds: [lo, hi] } => format!(
                "heterogeneous, sigma_t {} x scale {} per unit length inside the box {:?} to {:?}, albedo {}; delta tracking against the majorant {} (a line through its box meets {:.1} tentative collisions at most on average)",
                field(&self.sigma_t),
                self.scale,
                lo.to_array().map(round6),
                hi.to_array().map(round6),
                field(&self.albedo),
                self.majorant() as f32,
                self.collision_mean_bound()
            ),
        }
    }

    /// Its lines of the scene hash: a homogeneous medium of constant coefficients keeps the
    /// three it had before grids and heterogeneous media existed.
    pub fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        let field = |f: &Field, scale: f64| match f {
            Field::Constant(c) => vec3(*c * scale),
            Field::Grid(g) => Texture::Volume(g.clone()).hash_value(vec3),
        };
        match self.kind {
            MediumKind::Homogeneous => line("sigma_t", field(&self.sigma_t, self.scale)),
            MediumKind::Heterogeneous { bounds: [lo, hi] } => {
                line("kind", "heterogeneous".to_string());
                line("sigma_t", field(&self.sigma_t, 1.0));
                line("scale", real(self.scale));
                line("bounds", format!("{} {}", vec3(lo), vec3(hi)));
            }
        }
        line("albedo", field(&self.albedo, 1.0));
        line("g", real(self.phase.g()));
    }
}

/// The most null collisions the kernel tracks along one path segment or one shadow ray
/// (`MAX_NULL_COLLISIONS`; 0 without heterogeneous media). A straight line crosses each
/// medium's box once, over at most its diagonal, so its collisions are a Poisson count of mean
/// at most λ = Σ λ_m (`Medium::collision_mean_bound`); the bound is the smallest k with
/// Chernoff's bound P(N >= k) <= e^-λ (e λ / k)^k below `NULL_COLLISION_TAIL`.
pub fn max_null_collisions(media: &[Medium]) -> u32 {
    if !media.iter().any(Medium::is_heterogeneous) {
        return 0;
    }
    null_collision_bound(media.iter().map(Medium::collision_mean_bound).sum())
}

/// The smallest k >= λ with Chernoff's bound on a Poisson count of mean λ,
/// P(N >= k) <= e^-λ (e λ / k)^k, at most `NULL_COLLISION_TAIL` (at least 16).
pub fn null_collision_bound(lambda: f64) -> u32 {
    let target = NULL_COLLISION_TAIL.ln();
    let mut k = lambda.ceil().max(16.0);
    // ln of the bound: -λ + k (1 + ln λ - ln k), decreasing in k beyond λ.
    while lambda > 0.0 && -lambda + k * (1.0 + lambda.ln() - k.ln()) > target {
        k += (k * 0.01).max(1.0);
    }
    k.min(u32::MAX as f64) as u32
}

/// `v` to 6 decimals (for printing a box computed through a matrix inverse).
fn round6(v: f64) -> f64 {
    (v * 1e6).round() / 1e6
}

/// The world box of the unit cube under `to_world` (Mitsuba's `Volume::update_bbox`).
pub fn unit_cube_bounds(to_world: DMat4) -> [DVec3; 2] {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for i in 0..8 {
        let p = to_world.transform_point3(DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64));
        lo = lo.min(p);
        hi = hi.max(p);
    }
    [lo, hi]
}

/// The world box of a grid: its unit cube under the inverse of its world-to-grid map.
pub fn grid_bounds(g: &GridVolume) -> [DVec3; 2] {
    let r = g.to_local;
    let to_local = DMat4::from_cols_array_2d(&[r[0], r[1], r[2], [0.0, 0.0, 0.0, 1.0]]).transpose();
    unit_cube_bounds(to_local.inverse())
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
    /// The bound's tail, checked against the Poisson distribution's own (statrs), and its
    /// growth: about λ + 8 √λ.
    #[test]
    fn null_collision_bound_has_its_tail() {
        use statrs::distribution::{DiscreteCDF, Poisson};
        for lambda in [0.5, 4.0, 30.0, 500.0] {
            let k = null_collision_bound(lambda);
            let tail = Poisson::new(lambda).unwrap().sf(k as u64 - 1);
            assert!(tail <= NULL_COLLISION_TAIL, "λ {lambda}: P(N >= {k}) = {tail}");
            assert!((k as f64) < lambda + 10.0 * lambda.sqrt() + 40.0, "λ {lambda}: bound {k}");
        }
        assert_eq!(null_collision_bound(0.0), 16);
    }

    #[test]
    fn a_grids_bounds_are_its_to_worlds_cube() {
        let g = GridVolume::new("g.vol".into(), [1, 1, 1], 1, vec![1.0], true, crate::scene::textures::Wrap::Clamp, false, [[1.0 / 1.5, 0.0, 0.0, 0.5 / 1.5], [0.0, 1.0 / 1.5, 0.0, 0.5 / 1.5], [0.0, 0.0, 1.0 / 1.5, 0.5 / 1.5]]);
        let [lo, hi] = grid_bounds(&g);
        assert!((lo - DVec3::splat(-0.5)).length() < 1e-12 && (hi - DVec3::splat(1.0)).length() < 1e-12, "{lo} {hi}");
    }

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
