//! Mitsuba's `roughconductor` (WGSL: `shaders/bsdfs/rough_conductor.wgsl`): Torrance-Sparrow
//! microfacet reflection with the conductor's Fresnel term and separable Smith shadowing. TOML
//! the conductor's `eta`, `k` or `material`, `specular_reflectance`, and `distribution` (`beckmann`, Mitsuba's
//! default, or `ggx`) and `alpha` (default 0.1; below 1e-4 clamped to it, as Mitsuba does; or a
//! texture, Mitsuba's `eval_1` of it at the hit: `distribution::Roughness`), or `alpha_u` and
//! `alpha_v` (numbers or textures): anisotropic, along the surface's dp/du and across it.

use super::conductor::Conductor;
use super::distribution::{self, Distribution, Roughness};
use super::plugin::{BsdfData, BsdfParams, BsdfPlugin, Fields, PluginProps};

#[derive(Debug, Clone, PartialEq)]
pub struct RoughConductor {
    /// The Fresnel term.
    pub fresnel: Conductor,
    pub distribution: Distribution,
    /// The roughness, >= 1e-4, or a texture of it.
    pub roughness: Roughness,
}

impl BsdfPlugin for RoughConductor {
    const TOML_NAME: &'static str = "roughconductor";
    const FIELDS: &'static [&'static str] = &["distribution", "alpha", "alpha_u", "alpha_v", "eta", "k", "material", "specular_reflectance"];
    const MITSUBA_PLUGINS: &'static [&'static str] = &["roughconductor"];
    const IS_DELTA: bool = false;
    const MICROFACETS: bool = true;
    const TEXTURE_SLOTS: &'static [usize] = &[0, 1, 2];
    const SCALAR_TEXTURE_SLOTS: &'static [(usize, usize)] = &[(0, 3), (2, 3)];

    fn textures(&self) -> Vec<&crate::scene::Texture> {
        let mut t = self.fresnel.fresnel_textures();
        t.extend(self.roughness.textures());
        t
    }

    fn from_fields(f: &mut Fields) -> RoughConductor {
        let fresnel = Conductor::read_fresnel(f);
        let (distribution, roughness) = distribution::read_fields(f, "conductor", true, true);
        RoughConductor { fresnel, distribution, roughness }
    }

    fn from_mitsuba(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
        // The roughness first: a textured alpha is taken before the Fresnel reader refuses
        // other textures.
        let microfacets = distribution::read_mitsuba(p, true, true);
        let mut fields = Conductor::mitsuba_fresnel(p);
        p.finish("distribution, alpha, alpha_u, alpha_v, eta, k, material, specular_reflectance (and, with a warning, sample_visible)");
        fields.extend(microfacets?);
        Some(fields)
    }

    fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        self.fresnel.fresnel_hash_lines(line);
        line("conductor.rough", format!("{} {}", self.distribution, self.roughness.hash_value()));
    }

    fn pack(&self, data: &mut BsdfData) -> BsdfParams {
        let alpha = self.roughness.pack(data);
        let mut block = self.fresnel.pack_with(alpha, self.distribution, data);
        // p2.w: alpha_v, -0.0 where isotropic (WGSL's conductor_of).
        block[2][3] = self.roughness.pack_v(data);
        block
    }
}
