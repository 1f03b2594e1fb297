//! Mitsuba's `blendbsdf` (`src/bsdfs/blendbsdf.cpp`; WGSL: `blend_pick` in `shaders/scene.wgsl`):
//! a linear blend of two BSDFs by a weight w in [0, 1] (a number or a texture, read as Mitsuba's
//! `eval_1` and clipped),
//!
//!   f(wi, wo) = (1 - w) f_0(wi, wo) + w f_1(wi, wo).
//!
//! Mitsuba evaluates both and samples their mixture. pathlab picks one per path vertex instead:
//! f_1 with probability w (when the vertex's lobe sample u < w, which is then rescaled to u / w,
//! else to (u - w) / (1 - w), so the picked BSDF's own lobe choice sees a fresh uniform number),
//! and the vertex is that BSDF's: next event estimation, BSDF sampling and the MIS weights of
//! both are the picked BSDF's alone. Conditioned on the pick, the vertex's estimator is an
//! unbiased one of that BSDF's scattering, and the picks' probabilities are the blend's weights,
//! so its expectation is the blend's: the same image as Mitsuba's, with more variance where the
//! two BSDFs differ much (one evaluation and one kernel call per vertex instead of two, which a
//! SIMD CPU driver pays for in every pipeline).
//!
//! Not a kind of the registry: the blend is the material's own BSDF (f_0) and another material
//! whose BSDF is f_1 (`Material::blend`), as a `twosided`'s back is. Each BSDF keeps its own
//! sidedness (`twosided` around the blend makes both two-sided). TOML: `blend = "other"` and
//! `blend_weight = 0.3` (in [0, 1]) or a texture table; Mitsuba: `<bsdf type="blendbsdf">` with
//! `weight` (required, as Mitsuba's: a float, an `<rgb>` taken as its channels' mean, or a
//! texture) and two nested BSDFs.

use super::mask::Opacity;

/// A material's blend with another material's BSDF.
#[derive(Debug, Clone, PartialEq)]
pub struct Blend {
    /// The material (an index into `Scene::materials`) whose BSDF is f_1.
    pub material: usize,
    /// w, the weight of f_1: a number in [0, 1] or a texture, read and clipped as a mask's
    /// opacity is (`Opacity`: Mitsuba's `eval_1`, clipped to [0, 1]).
    pub weight: Opacity,
}
