//! The normalised modified Phong BRDF (the study's; WGSL: `shaders/bsdfs/phong.wgsl`),
//!
//!   f(wi, wo) = kd / pi + ks (n + 2) / (2 pi) max(0, dot(wi, r))^n,   r = mirror of wo,
//!
//! TOML `diffuse`, `specular`, `glossiness`; Mitsuba's `diffuse` (a Phong BRDF without lobe)
//! and the reference renderer's `modphong`.

use glam::DVec3;

use super::plugin::{color_value, BsdfData, BsdfParams, BsdfPlugin, Fields, PluginProps};
use crate::scene::emitters::luminance;
use crate::scene::textures::Texture;

/// Mitsuba's default reflectance of `diffuse` (and the reference renderer's `kd`).
pub(crate) const DEFAULT_REFLECTANCE: f64 = 0.5;

#[derive(Debug, Clone, PartialEq)]
pub struct Phong {
    /// kd (a texture's mean where `diffuse_texture` is given).
    pub diffuse: DVec3,
    /// A texture of the diffuse reflectance (Mitsuba's textured `reflectance`).
    pub diffuse_texture: Option<Texture>,
    /// ks.
    pub specular: DVec3,
    /// The exponent n.
    pub glossiness: f64,
}

impl Phong {
    /// A black Phong material (every parameter zero).
    pub const BLACK: Phong = Phong { diffuse: DVec3::ZERO, diffuse_texture: None, specular: DVec3::ZERO, glossiness: 0.0 };
}

impl BsdfPlugin for Phong {
    const TOML_NAME: &'static str = "phong";
    const FIELDS: &'static [&'static str] = &["diffuse", "specular", "glossiness"];
    const MITSUBA_PLUGINS: &'static [&'static str] = &["diffuse", "modphong"];
    const IS_DELTA: bool = false;
    const TEXTURE_SLOTS: &'static [usize] = &[0];

    fn from_fields(f: &mut Fields) -> Phong {
        let (diffuse, diffuse_texture) = f.color_or_texture("diffuse", DVec3::ZERO);
        let specular = f.color("specular", DVec3::ZERO);
        let glossiness = match f.number("glossiness") {
            Some(n) => {
                let v = *n.get_ref();
                if v < 0.0 {
                    f.error(n.span(), "glossiness", format!("glossiness must be >= 0 (got {v})"));
                }
                v
            }
            None => {
                if !f.has("glossiness") && specular.max_element() > 0.0 {
                    f.error(f.span(), "glossiness", "glossiness is required when specular is non-zero");
                }
                0.0
            }
        };
        let total = diffuse + specular;
        if total.max_element() > 1.0 {
            f.warn_material(format!("diffuse + specular = {:?} exceeds 1: the material is not energy conserving", total.to_array()));
        }
        Phong { diffuse, diffuse_texture, specular, glossiness }
    }

    fn from_mitsuba(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
        let (kd, ks, n) = if p.plugin() == "diffuse" {
            let kd = p.color_or_texture("reflectance").unwrap_or_else(|| color_value([DEFAULT_REFLECTANCE; 3]));
            p.finish("reflectance");
            (kd, [0.0; 3], 0.0)
        } else {
            // The reference renderer's normalised modified Phong (shared/reference-renderer).
            let kd = p.color("kd").unwrap_or([DEFAULT_REFLECTANCE; 3]);
            let ks = p.color("ks").unwrap_or([0.0; 3]);
            let n = p.float("n").map_or(0.0, |n| n.0);
            p.finish("kd, ks, n");
            if !(n.is_finite() && n >= 0.0) {
                let at = p.at();
                p.error(at, "n", format!("`n` of <bsdf type=\"modphong\"> must be finite and >= 0 (got {n})"));
            }
            (color_value(kd), ks, n)
        };
        let mut fields = vec![("diffuse", kd)];
        if ks.iter().any(|&s| s > 0.0) {
            fields.push(("specular", color_value(ks)));
            fields.push(("glossiness", toml::Value::Float(n)));
        }
        Some(fields)
    }

    fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        line("diffuse", crate::scene::hash::vec3(self.diffuse));
        // Only a textured one adds a line: untextured scenes keep their hash.
        if let Some(t) = &self.diffuse_texture {
            line("diffuse.texture", t.hash_value(crate::scene::hash::vec3));
        }
        line("specular", crate::scene::hash::vec3(self.specular));
        line("glossiness", crate::scene::hash::real(self.glossiness));
    }

    fn textures(&self) -> Vec<&Texture> {
        self.diffuse_texture.iter().collect()
    }

    /// `p0 = (kd, n)`, `p1 = (ks, p_spec)` with p_spec the probability of sampling the Phong
    /// lobe, the luminance ratio lum(ks) / (lum(kd) + lum(ks)).
    fn pack(&self, data: &mut BsdfData) -> BsdfParams {
        let (ld, ls) = (luminance(self.diffuse), luminance(self.specular));
        let p_spec = if ld + ls > 0.0 { ls / (ld + ls) } else { 0.0 };
        // A texture: the reference -(start + 1) of its record in the BSDF data (texture.wgsl).
        let d = match &self.diffuse_texture {
            Some(t) => glam::Vec3::new(-(t.pack(data) as f32) - 1.0, 0.0, 0.0),
            None => self.diffuse.as_vec3(),
        };
        let s = self.specular.as_vec3();
        [[d.x, d.y, d.z, self.glossiness as f32], [s.x, s.y, s.z, p_spec as f32], [0.0; 4], [0.0; 4]]
    }
}
