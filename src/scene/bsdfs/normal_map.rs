//! Mitsuba's `normalmap` (`src/bsdfs/normalmap.cpp`; WGSL: `shaders/bsdfs/normal_map.wgsl`): a
//! texture of normals wrapped around a material's BSDF, which then scatters in the perturbed
//! shading frame. A texel c gives the normal n = 2 c - 1 relative to the surface's shading frame
//! (s from its dp/du, t = n x s, the shading normal), flipped about that normal, (-x, -y, z),
//! where the viewer sees its back (Mitsuba's `flip_invalid_normals`, Schüssler et al. 2017); the
//! perturbed frame is (s', n' x s', n') with s' = normalize(x - n' n'.x). The nested BSDF is
//! evaluated and sampled in it, zero for directions on different sides of the two normals, its
//! value times Estevez et al.'s shadowing term 2 / (1 + sqrt(1 + a^2 tan^2(theta_i))), a^2 =
//! min(tan^2(theta_n') / 8, 1) (Mitsuba's `use_shadowing_function`).
//!
//! Not a kind of the registry: any reflecting kind may be normal-mapped, so the map is the
//! material's (`Material::normal_map`). TOML: `normal_map = { texture = "bitmap", filename =
//! "normals.png", raw = true }` (a bitmap, the only texture with Mitsuba's `eval_3`; normals want
//! `raw`, as Mitsuba's documentation says); Mitsuba: `<bsdf type="normalmap">` with a `<texture name="normalmap">`
//! and one nested BSDF.

use std::ops::Range;
use std::path::Path;

use crate::scene::bsdf_data::BsdfData;
use crate::scene::textures::Texture;

/// A material's normal map: a colour texture whose texels encode normals as (n + 1) / 2.
#[derive(Debug, Clone, PartialEq)]
pub struct NormalMap {
    pub texture: Texture,
}

impl NormalMap {
    /// Its number in the material record (`Material.normal_map`, scene.wgsl): the start of its
    /// texture's record in `data`.
    pub fn pack(&self, data: &mut BsdfData) -> u32 {
        self.texture.pack(data)
    }

    /// Its value in the scene hash.
    pub fn hash_value(&self) -> String {
        self.texture.hash_value(crate::scene::hash::vec3)
    }

    /// Its TOML field's value.
    pub fn to_toml(&self) -> toml::Value {
        self.texture.to_toml()
    }

    /// A material's `normal_map` field (a texture table, image files relative to `base`);
    /// errors as (span, message).
    pub(crate) fn from_toml(value: &toml::Value, span: Range<usize>, base: &Path) -> Result<NormalMap, Vec<(Range<usize>, String)>> {
        match value {
            toml::Value::Table(table) => {
                let mut errors = Vec::new();
                match Texture::from_toml(table, span.clone(), base, &mut errors) {
                    Some(texture @ (Texture::Bitmap(_) | Texture::RawConstant { .. })) if errors.is_empty() => Ok(NormalMap { texture }),
                    // Mitsuba's normalmap reads eval_3, which only its bitmap and rawconstant
                    // have (its checkerboard fails at render time: "Texture::eval_3(): not
                    // implemented!").
                    Some(t) if errors.is_empty() => Err(vec![(span, format!("a normal map must be a bitmap or a rawconstant (Mitsuba's {} texture has no eval_3, which its normalmap reads)", t.name()))]),
                    _ => Err(errors),
                }
            }
            v => Err(vec![(span, format!("`normal_map` must be a texture table, e.g. {{ texture = \"bitmap\", filename = \"normals.png\", raw = true }} (got {v})"))]),
        }
    }
}
