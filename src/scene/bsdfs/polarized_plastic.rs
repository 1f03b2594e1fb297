//! Mitsuba's `pplastic` (WGSL: `shaders/bsdfs/polarized_plastic.wgsl`) as Mitsuba 3's RGB
//! variants evaluate it (`pplastic.cpp`, its unpolarised branch): Baek et al.'s (2018) ad-hoc sum
//! of a rough specular reflection and a diffuse lobe attenuated by two smooth refractions,
//!
//!   f_spec(wi, wo) = s F(wo . h) D(h) G(wo, wi, h) / (4 cos_o cos_i),
//!   f_diff(wi, wo) = R (1 - F(cos_o)) (1 - F(cos_i)) / pi,
//!
//! with F the dielectric Fresnel reflectance of relative index eta, D and G the microfacet
//! distribution (Beckmann by default, or GGX; `alpha`, or `alpha_u` and `alpha_v`, each a
//! number or a texture) and its separable Smith shadowing, R = `diffuse_reflectance` (default
//! 0.5, or a texture), s = `specular_reflectance` (default 1). Unlike `roughplastic` there are
//! no internal reflections and no 1 / eta^2: Mitsuba's documentation calls it "not energy
//! conserving". Mitsuba's polarised variants add the Mueller matrices of the same terms; an RGB
//! image of the intensity is this. Its own sampling picks the specular lobe with the fixed
//! probability w = mean(s) / (mean(R) + mean(s)) (Mitsuba's `m_specular_sampling_weight`; no
//! Fresnel-weighted choice, so `--lobe-selection` does not apply), reflecting about a normal of
//! the pipeline's `--microfacet-sampling`, else a cosine-weighted direction. One sided.
//!
//! TOML: `bsdf = "pplastic"` with `diffuse_reflectance`, `specular_reflectance`, `int_ior`,
//! `ext_ior` (polypropylene in air by default, numbers or names), `distribution`, `alpha` or
//! `alpha_u` and `alpha_v`. Mitsuba: the same, or `eta` (a `<float>`, the relative index) instead
//! of the two indices (both refused, and equal indices refused, as Mitsuba's constructor does).

use glam::DVec3;

use super::distribution::{self, Distribution, Roughness};
use super::ior::{self, DEFAULT_EXT_IOR};
use super::plastic::Plastic;
use super::plugin::{color_value, BsdfData, BsdfParams, BsdfPlugin, Fields, PluginProps};
use crate::scene::hash::{real, vec3};
use crate::scene::textures::Texture;

/// Mitsuba's default interior index (`polypropylene`).
const DEFAULT_INT_IOR: f64 = 1.49;

#[derive(Debug, Clone, PartialEq)]
pub struct PolarizedPlastic {
    /// R (a texture's mean where `diffuse_texture` is given).
    pub diffuse: DVec3,
    pub diffuse_texture: Option<Texture>,
    /// s.
    pub specular: DVec3,
    /// The relative index eta = int_ior / ext_ior.
    pub eta: f64,
    pub distribution: Distribution,
    pub roughness: Roughness,
}

impl PolarizedPlastic {
    /// Mitsuba's `m_specular_sampling_weight`, as plastic's (`Plastic::specular_sampling_weight`).
    pub fn specular_sampling_weight(&self) -> f64 {
        self.as_layers().specular_sampling_weight()
    }

    /// The base and the coating's albedo as a smooth plastic's layers (for the shared helpers).
    fn as_layers(&self) -> Plastic {
        Plastic {
            diffuse: self.diffuse,
            diffuse_texture: self.diffuse_texture.clone(),
            specular: self.specular,
            int_ior: self.eta,
            ext_ior: 1.0,
            nonlinear: false,
        }
    }
}

impl BsdfPlugin for PolarizedPlastic {
    const TOML_NAME: &'static str = "pplastic";
    const FIELDS: &'static [&'static str] =
        &["diffuse_reflectance", "specular_reflectance", "int_ior", "ext_ior", "distribution", "alpha", "alpha_u", "alpha_v"];
    const MITSUBA_PLUGINS: &'static [&'static str] = &["pplastic"];
    const IS_DELTA: bool = false;
    const MICROFACETS: bool = true;
    const TEXTURE_SLOTS: &'static [usize] = &[0];
    const SCALAR_TEXTURE_SLOTS: &'static [(usize, usize)] = &[(2, 0), (2, 3)];

    fn from_fields(f: &mut Fields) -> PolarizedPlastic {
        // The base, the coating's albedo and the indices as a plastic's (with its defaults and
        // checks; `nonlinear` is not a field of this kind, so it stays false).
        let layers = Plastic::from_fields(f);
        let (distribution, roughness) = distribution::read_fields(f, "plastic", true, true);
        PolarizedPlastic { eta: layers.eta(), diffuse: layers.diffuse, diffuse_texture: layers.diffuse_texture, specular: layers.specular, distribution, roughness }
    }

    fn from_mitsuba(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
        // The roughness first: a textured alpha is taken before other textures are refused.
        let microfacets = distribution::read_mitsuba(p, true, true);
        let mut fields = Vec::new();
        if let Some(d) = p.color_or_texture("diffuse_reflectance") {
            fields.push(("diffuse_reflectance", d));
        }
        if let Some(c) = p.color("specular_reflectance") {
            fields.push(("specular_reflectance", color_value(c)));
        }
        // Mitsuba's constructor: `eta`, or the two indices (polypropylene in air), which must
        // differ; not both.
        let given_indices = p.has("int_ior") || p.has("ext_ior");
        match p.float("eta") {
            Some((eta, at)) => {
                if given_indices {
                    p.error(at, "eta", "give either `eta` or `int_ior` and `ext_ior`, not both (as Mitsuba requires)".into());
                } else if !(eta.is_finite() && eta > 0.0) {
                    p.error(at, "eta", format!("`eta` of <bsdf type=\"pplastic\"> must be a finite relative index > 0 (got {eta})"));
                }
                fields.push(("int_ior", toml::Value::Float(eta)));
                fields.push(("ext_ior", toml::Value::Float(1.0)));
            }
            None => {
                let at = p.at();
                let int_ior = ior::from_mitsuba(p, "int_ior", DEFAULT_INT_IOR);
                let ext_ior = ior::from_mitsuba(p, "ext_ior", DEFAULT_EXT_IOR);
                if int_ior == ext_ior {
                    p.error(at, "int_ior", format!("the interior and exterior indices of refraction must differ (both {int_ior}), as Mitsuba requires"));
                }
                fields.push(("int_ior", toml::Value::Float(int_ior)));
                fields.push(("ext_ior", toml::Value::Float(ext_ior)));
            }
        }
        if let Some(at) = p.texture() {
            p.error(at, "", "a textured parameter other than diffuse_reflectance and the roughness is not supported (give <rgb> or <float> values)".into());
        }
        p.finish("diffuse_reflectance, specular_reflectance, int_ior, ext_ior, eta, distribution, alpha, alpha_u, alpha_v (and, with a warning, sample_visible)");
        fields.extend(microfacets?);
        Some(fields)
    }

    fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        line("pplastic.diffuse", vec3(self.diffuse));
        if let Some(t) = &self.diffuse_texture {
            line("pplastic.diffuse.texture", t.hash_value(vec3));
        }
        line("pplastic.specular", vec3(self.specular));
        line("pplastic.eta", real(self.eta));
        line("pplastic.rough", format!("{} {}", self.distribution, self.roughness.hash_value()));
    }

    fn textures(&self) -> Vec<&Texture> {
        self.diffuse_texture.iter().chain(self.roughness.textures()).collect()
    }

    /// `p0 = (diffuse, eta)`, `p1 = (specular, specular_sampling_weight)`, `p2 = (alpha_u,
    /// distribution, 0, alpha_v)`: the layout of WGSL's `polarized_plastic_of` (alpha_v -0.0
    /// where isotropic, `Roughness::pack_v`).
    fn pack(&self, data: &mut BsdfData) -> BsdfParams {
        let (d, s) = (self.as_layers().diffuse_slot(data), self.specular.as_vec3());
        [
            [d.x, d.y, d.z, self.eta as f32],
            [s.x, s.y, s.z, self.specular_sampling_weight() as f32],
            [self.roughness.pack(data), self.distribution.constant() as f32, 0.0, self.roughness.pack_v(data)],
            [0.0; 4],
        ]
    }
}
