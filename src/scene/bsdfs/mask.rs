//! Mitsuba's `mask` (`src/bsdfs/mask.cpp`; WGSL: `shaders/bsdfs/mask.wgsl`): an opacity wrapped
//! around any material's BSDF. A ray that meets the surface scatters off it with probability
//! `opacity` (by the nested BSDF) and otherwise passes straight through, a null interaction:
//!
//!   f_mask(wi, wo) = opacity f(wi, wo),   pdf_mask(wi) = opacity pdf(wi),
//!
//! plus a delta lobe of mass 1 - opacity in the direction -wo. Its sampling picks that lobe when
//! u_lobe >= opacity (weight 1, pdf 1 - opacity, a delta: emission found along it gets MIS
//! weight 1), else draws from the nested BSDF with u_lobe / opacity (its weight unchanged, its
//! pdf times opacity). As in Mitsuba 3.9.1's path tracer, the pass-through is a vertex of the
//! path (it counts towards `max_depth` and meets roulette), and shadow rays do not see through
//! a mask: light reaching a point through a mask arrives by the pass-through chain alone, with
//! MIS weight 1, so nothing is counted twice or lost.
//!
//! Not a kind of the registry: any kind may be masked, so the opacity is the material's
//! (`Material::opacity`). TOML: `opacity = 0.3` (in [0, 1]) or a texture table
//! (`opacity = { texture = "bitmap", filename = "leaf_mask.png" }`); Mitsuba: `<bsdf
//! type="mask">` with `opacity` (a float, an `<rgb>`, a texture; default 0.5) and one nested
//! BSDF. A texture's value is Mitsuba's `eval_1`: the luminance of a bitmap's linear RGB, the
//! mean of a constant's or a checkerboard colour's channels, with the checkerboard's colours in
//! each other's places (Mitsuba 3.9.1's quirk, kept: see `Texture::scalar`); clipped to [0, 1].

use std::ops::Range;
use std::path::Path;

use crate::scene::bsdf_data::BsdfData;
use crate::scene::emitters::luminance;
use crate::scene::hash::real;
use crate::scene::textures::Texture;

/// Mitsuba's `opacity` when a `mask` gives none.
pub const DEFAULT_MITSUBA_OPACITY: f64 = 0.5;

/// A material's opacity: the probability that a ray meeting its surface scatters off it.
#[derive(Debug, Clone, PartialEq)]
pub enum Opacity {
    /// The same everywhere, in [0, 1).
    Constant(f64),
    /// Looked up at the hit's uv parametrisation (`of_texture`): a checkerboard's colours are
    /// their channel means (grey), a bitmap's texels their luminance.
    Texture(Texture),
}

impl Opacity {
    /// A texture as Mitsuba's `eval_1` reads it (`Texture::scalar`).
    pub fn of_texture(t: Texture) -> Opacity {
        Opacity::Texture(t.scalar())
    }

    /// Its value at `uv` and world position `p`, in f32 as the kernel computes it
    /// (`material_opacity`): the host twin.
    pub fn eval(&self, uv: [f32; 2], p: [f32; 3]) -> f32 {
        match self {
            Opacity::Constant(o) => *o as f32,
            Opacity::Texture(t) => t.eval_1(uv, p).clamp(0.0, 1.0),
        }
    }

    /// Its mean over the uv square (what `pathlab check` reports).
    pub fn mean(&self) -> f64 {
        match self {
            Opacity::Constant(o) => *o,
            Opacity::Texture(t) => luminance(t.mean()).clamp(0.0, 1.0),
        }
    }

    /// Its texture, if it is one.
    pub fn texture(&self) -> Option<&Texture> {
        match self {
            Opacity::Constant(_) => None,
            Opacity::Texture(t) => Some(t),
        }
    }

    /// Its number in the material record (`Material.opacity`, scene.wgsl): the constant, or, for
    /// a texture, the reference -(start + 1) of its record in `data`.
    pub fn pack(&self, data: &mut BsdfData) -> f32 {
        match self {
            Opacity::Constant(o) => *o as f32,
            Opacity::Texture(t) => -(t.pack(data) as f32) - 1.0,
        }
    }

    /// Its value in the scene hash.
    pub fn hash_value(&self) -> String {
        match self {
            Opacity::Constant(o) => real(*o),
            Opacity::Texture(t) => t.hash_value(crate::scene::hash::vec3),
        }
    }

    /// Its TOML field's value.
    pub fn to_toml(&self) -> toml::Value {
        match self {
            Opacity::Constant(o) => toml::Value::Float(*o),
            Opacity::Texture(t) => t.to_toml(),
        }
    }

    /// A material's `opacity` field (a number in [0, 1] or a texture table, image files relative
    /// to `base`): `Ok(None)` for 1 (opaque: no mask), errors as (span, message).
    pub(crate) fn from_toml(value: &toml::Value, span: Range<usize>, base: &Path) -> Result<Option<Opacity>, Vec<(Range<usize>, String)>> {
        Opacity::weight_from_toml(value, span, base, "opacity").map(|o| (o != Opacity::Constant(1.0)).then_some(o))
    }

    /// A weight in [0, 1] (a mask's `opacity`, a blend's `blend_weight`, the field `name`): a
    /// number or a texture table (image files relative to `base`), errors as (span, message).
    pub(crate) fn weight_from_toml(value: &toml::Value, span: Range<usize>, base: &Path, name: &str) -> Result<Opacity, Vec<(Range<usize>, String)>> {
        match value {
            toml::Value::Table(table) => {
                let mut errors = Vec::new();
                match Texture::from_toml(table, span, base, &mut errors) {
                    Some(t) if errors.is_empty() => Ok(Opacity::of_texture(t)),
                    _ => Err(errors),
                }
            }
            v => match v.as_float().or_else(|| v.as_integer().map(|i| i as f64)) {
                Some(w) if (0.0..=1.0).contains(&w) => Ok(Opacity::Constant(w)),
                _ => Err(vec![(span, format!("`{name}` must be a number in [0, 1] or a texture table (got {v})"))]),
            },
        }
    }
}

