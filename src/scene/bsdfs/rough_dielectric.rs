//! Mitsuba's `roughdielectric` (WGSL: `shaders/bsdfs/rough_dielectric.wgsl`): Walter et al.'s
//! (2007) microfacet model of a rough interface between two indices of refraction, reflecting
//! and refracting about microfacet normals with the Fresnel term of unpolarised light,
//!
//!   f_r = F(wo . m) D(m) G(wo, wi, m) / (4 |cos_o| |cos_i|),                    m the half vector,
//!   f_t = (1 - F) D G |wo . m| |wi . m| / (|cos_o| |cos_i| (wo . m + eta wi . m)^2),
//!
//! (in radiance transport; m = normalize(wo + eta wi) for refraction), term for term as
//! Mitsuba 3's `roughdielectric.cpp`. Its own sampling draws a normal by the pipeline's
//! microfacet strategy (`--microfacet-sampling`: visible normals, or the distribution with
//! Walter's roughness scaled by 1.2 - 0.2 sqrt|cos_o|, as Mitsuba does without
//! `sample_visible`), then reflects with probability F or refracts. Both sides scatter. TOML and
//! Mitsuba: `int_ior`, `ext_ior` (defaults bk7 and air; numbers or names of `ior.rs`; they must
//! differ), `specular_reflectance`, `specular_transmittance`, `distribution`, `alpha` (a number or
//! a texture: `distribution::Roughness`) or `alpha_u` and `alpha_v` (numbers or textures;
//! anisotropic along the surface's dp/du and across it).

use glam::DVec3;

use super::distribution::{self, Distribution, Roughness};
use super::ior::{Interface, InterfaceTextures};
use super::plugin::{BsdfData, BsdfParams, BsdfPlugin, Fields, PluginProps};
use crate::scene::hash::{real, vec3};

#[derive(Debug, Clone, PartialEq)]
pub struct RoughDielectric {
    pub int_ior: f64,
    pub ext_ior: f64,
    /// Factors on the reflected and the refracted lobe (1: Mitsuba's default).
    pub reflectance: DVec3,
    pub transmittance: DVec3,
    /// Textures of the two factors, where given.
    pub textures: InterfaceTextures,
    pub distribution: Distribution,
    /// The roughness, >= 1e-4, or a texture of it.
    pub roughness: Roughness,
}

impl RoughDielectric {
    /// The relative index eta = int_ior / ext_ior.
    pub fn eta(&self) -> f64 {
        self.int_ior / self.ext_ior
    }
}

impl BsdfPlugin for RoughDielectric {
    const TOML_NAME: &'static str = "roughdielectric";
    const FIELDS: &'static [&'static str] = &["int_ior", "ext_ior", "specular_reflectance", "specular_transmittance", "distribution", "alpha", "alpha_u", "alpha_v"];
    const MITSUBA_PLUGINS: &'static [&'static str] = &["roughdielectric"];
    const IS_DELTA: bool = false;
    const TRANSMITS: bool = true;
    const BOTH_SIDES: bool = true;
    const MICROFACETS: bool = true;
    const SCALAR_TEXTURE_SLOTS: &'static [(usize, usize)] = &[(1, 3), (2, 1)];
    const TEXTURE_SLOTS: &'static [usize] = &InterfaceTextures::SLOTS;

    fn textures(&self) -> Vec<&crate::scene::Texture> {
        let mut all = self.textures.all();
        all.extend(self.roughness.textures());
        all
    }

    fn from_fields(f: &mut Fields) -> RoughDielectric {
        let Interface { int_ior, ext_ior, reflectance, transmittance, textures } = Interface::from_fields(f);
        if int_ior == ext_ior {
            f.error(f.span(), "int_ior", format!("int_ior and ext_ior must differ (both {int_ior}), as Mitsuba requires: an index-matched interface scatters nothing"));
        }
        let (distribution, roughness) = distribution::read_fields(f, "dielectric", true, true);
        RoughDielectric { int_ior, ext_ior, reflectance, transmittance, textures, distribution, roughness }
    }

    fn from_mitsuba(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
        // The roughness first: a textured alpha is taken before the interface's reader refuses
        // other textures.
        let microfacets = distribution::read_mitsuba(p, true, true);
        let mut fields = Interface::mitsuba_fields(p);
        p.finish("int_ior, ext_ior, specular_reflectance, specular_transmittance, distribution, alpha, alpha_u, alpha_v (and, with a warning, sample_visible)");
        fields.extend(microfacets?);
        Some(fields)
    }

    fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        line("roughdielectric.int_ior", real(self.int_ior));
        line("roughdielectric.ext_ior", real(self.ext_ior));
        line("roughdielectric.reflectance", vec3(self.reflectance));
        line("roughdielectric.transmittance", vec3(self.transmittance));
        self.textures.hash_lines("roughdielectric", line);
        line("roughdielectric.microfacets", format!("{} {}", self.distribution.name(), self.roughness.hash_value()));
    }

    /// `p0 = (reflectance, eta)`, `p1 = (transmittance, alpha)`, `p2 = (distribution, alpha_v
    /// (a number or a texture's reference) or -0.0 where isotropic, 0, 0)`: the layout of WGSL's `rough_dielectric_of`.
    fn pack(&self, data: &mut BsdfData) -> BsdfParams {
        let [r, t] = self.textures.pack(self.reflectance, self.transmittance, data);
        [[r.x, r.y, r.z, self.eta() as f32], [t.x, t.y, t.z, self.roughness.pack(data)], [self.distribution.constant() as f32, self.roughness.pack_v(data), 0.0, 0.0], [0.0; 4]]
    }
}
