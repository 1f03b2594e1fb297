//! Mitsuba's `bumpmap` (`src/bsdfs/bumpmap.cpp`; WGSL: `shaders/bsdfs/bump_map.wgsl`): a height
//! texture wrapped around a material's BSDF, which then scatters in the frame of the bumped
//! surface. With g = scale (dh/du, dh/dv), the texture's gradient in uv (Mitsuba's bitmap
//! `eval_1_grad`: the bilinear interpolant's partials, `Bitmap::eval_1_grad` here), the surface's
//! partials get g as their component along the shading normal n,
//!   dp/du' = dp/du + n (g.x - n . dp/du),   dp/dv' = dp/dv + n (g.y - n . dp/dv),
//! and the bumped normal is normalize(dp/du' x dp/dv'), turned to the side of the geometric
//! normal. From there it is the normal map's frame (`NormalMap`): the normal taken into the
//! shading frame, flipped about the shading normal where the viewer sees its back
//! (`flip_invalid_normals`), the nested BSDF evaluated and sampled in it with Estevez et al.'s
//! shadowing term (`use_shadowing_function`).
//!
//! Not a kind of the registry: any reflecting kind may be bump-mapped, so the map is the
//! material's (`Material::bump_map`). TOML: `bump_map = { scale = 0.02, texture = "bitmap",
//! filename = "heights.png", raw = true }` (`scale` 1 when not given, as Mitsuba's; the rest is
//! the texture's table). Mitsuba: `<bsdf type="bumpmap">` with a `<float name="scale">`, one
//! `<texture>` of any name and one nested BSDF. The texture must be a bitmap: Mitsuba 3.9.1
//! gives a gradient (`eval_1_grad`) for no other.

use std::ops::Range;
use std::path::Path;

use crate::scene::bsdf_data::BsdfData;
use crate::scene::textures::Texture;

/// Mitsuba's `scale` by default.
pub const DEFAULT_BUMP_SCALE: f64 = 1.0;

/// A material's bump map: a height texture and the factor on its gradient.
#[derive(Debug, Clone, PartialEq)]
pub struct BumpMap {
    pub texture: Texture,
    pub scale: f64,
}

impl BumpMap {
    /// Its record in the BSDF data (`Material.bump_map`, scene.wgsl): the scale, then its
    /// texture's record; returns where it starts.
    pub fn pack(&self, data: &mut BsdfData) -> u32 {
        let start = data.push(&[self.scale as f32]);
        self.texture.pack(data);
        start
    }

    /// Its value in the scene hash.
    pub fn hash_value(&self) -> String {
        format!("scale {} {}", crate::scene::hash::real(self.scale), self.texture.hash_value(crate::scene::hash::vec3))
    }

    /// Its TOML field's value: the texture's table with `scale`.
    pub fn to_toml(&self) -> toml::Value {
        let mut value = self.texture.to_toml();
        if let toml::Value::Table(t) = &mut value {
            t.insert("scale".into(), toml::Value::Float(self.scale));
        }
        value
    }

    /// A material's `bump_map` field (a texture table with an optional `scale`, image files
    /// relative to `base`); errors as (span, message).
    pub(crate) fn from_toml(value: &toml::Value, span: Range<usize>, base: &Path) -> Result<BumpMap, Vec<(Range<usize>, String)>> {
        let toml::Value::Table(table) = value else {
            return Err(vec![(span, format!("`bump_map` must be a texture table, e.g. {{ scale = 0.02, texture = \"bitmap\", filename = \"heights.png\", raw = true }} (got {value})"))]);
        };
        let mut table = table.clone();
        let scale = match table.remove("scale") {
            None => DEFAULT_BUMP_SCALE,
            Some(v) => match v.as_float().or_else(|| v.as_integer().map(|i| i as f64)) {
                Some(s) if s.is_finite() => s,
                _ => return Err(vec![(span, format!("`scale` of a bump map must be a finite number (got {v})"))]),
            },
        };
        let mut errors = Vec::new();
        match Texture::from_toml(&table, span.clone(), base, &mut errors) {
            Some(texture @ Texture::Bitmap(_)) if errors.is_empty() => Ok(BumpMap { texture, scale }),
            // Mitsuba's bumpmap reads eval_1_grad, which only its bitmap has.
            Some(t) if errors.is_empty() => Err(vec![(span, format!("a bump map must be a bitmap (Mitsuba's {} texture has no gradient, eval_1_grad, which its bumpmap reads)", t.name()))]),
            _ => Err(errors),
        }
    }
}
