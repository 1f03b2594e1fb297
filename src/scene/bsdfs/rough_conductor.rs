//! Mitsuba's `roughconductor` (WGSL: `shaders/bsdfs/rough_conductor.wgsl`): Torrance-Sparrow
//! microfacet reflection with the conductor's Fresnel term and separable Smith shadowing. TOML
//! the conductor's `eta`, `k` or `material`, `specular_reflectance`, and `distribution` (`beckmann`, Mitsuba's
//! default, or `ggx`) and `alpha` (default 0.1; below 1e-4 clamped to it, as Mitsuba does).

use super::conductor::Conductor;
use super::distribution::{self, Distribution};
use super::plugin::{BsdfData, BsdfParams, BsdfPlugin, Fields, PluginProps};

#[derive(Debug, Clone, PartialEq)]
pub struct RoughConductor {
    /// The Fresnel term.
    pub fresnel: Conductor,
    pub distribution: Distribution,
    /// The roughness, >= 1e-4.
    pub alpha: f64,
}

impl BsdfPlugin for RoughConductor {
    const TOML_NAME: &'static str = "roughconductor";
    const FIELDS: &'static [&'static str] = &["distribution", "alpha", "eta", "k", "material", "specular_reflectance"];
    const MITSUBA_PLUGINS: &'static [&'static str] = &["roughconductor"];
    const IS_DELTA: bool = false;
    const MICROFACETS: bool = true;
    const TEXTURE_SLOTS: &'static [usize] = &[2];

    fn textures(&self) -> Vec<&crate::scene::Texture> {
        self.fresnel.reflectance_texture.iter().collect()
    }

    fn from_fields(f: &mut Fields) -> RoughConductor {
        let fresnel = Conductor::read_fresnel(f);
        let (distribution, alpha) = distribution::read_fields(f, "conductor");
        RoughConductor { fresnel, distribution, alpha }
    }

    fn from_mitsuba(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
        let mut fields = Conductor::mitsuba_fresnel(p);
        let microfacets = distribution::read_mitsuba(p);
        p.finish("distribution, alpha, eta, k, material, specular_reflectance (and, with a warning, sample_visible)");
        fields.extend(microfacets?);
        Some(fields)
    }

    fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        self.fresnel.fresnel_hash_lines(line);
        line("conductor.rough", format!("{} {}", self.distribution, crate::scene::hash::real(self.alpha)));
    }

    fn pack(&self, data: &mut BsdfData) -> BsdfParams {
        self.fresnel.pack_with(self.alpha, self.distribution, data)
    }
}
