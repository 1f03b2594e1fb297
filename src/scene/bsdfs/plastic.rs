//! Mitsuba's smooth `plastic` (WGSL: `shaders/bsdfs/plastic.wgsl`): a diffuse base under a
//! smooth dielectric coating, term for term as Mitsuba 3's `plastic.cpp`. A delta lobe reflects
//! the Fresnel reflectance F(cos_i) of the coating in the mirror direction (times
//! `specular_reflectance`); the rest enters, scatters diffusely inside with the internal
//! reflections summed in closed form, and leaves:
//!
//!   f(wi, wo) = R / (1 - fdr_int) (1 - F(cos_i)) (1 - F(cos_o)) / (pi eta^2)
//!
//! with R = `diffuse_reflectance`, `nonlinear` replacing 1 - fdr_int by 1 - R fdr_int (the
//! colour shift of internal scattering), fdr_int Mitsuba's fit of the diffuse Fresnel
//! reflectance seen from inside (`fresnel_diffuse_reflectance(1 / eta)`). Its own sampling picks
//! the delta lobe with probability F w / (F w + (1 - F)(1 - w)), w = `specular_sampling_weight`
//! = mean(specular) / (mean(diffuse) + mean(specular)), else a cosine-weighted direction. One
//! sided. TOML and Mitsuba: `diffuse_reflectance` (default 0.5), `specular_reflectance`
//! (default 1), `int_ior` (default 1.49, `polypropylene`), `ext_ior` (default 1.000277, `air`),
//! each a number or a name of `ior.rs`, and `nonlinear` (default false).

use glam::DVec3;

use super::ior::{self, DEFAULT_EXT_IOR};
use super::plugin::{color_value, BsdfData, BsdfParams, BsdfPlugin, Fields, PluginProps};
use crate::scene::hash::{real, vec3};
use crate::scene::textures::Texture;

/// Mitsuba's default interior index (`polypropylene`).
const DEFAULT_INT_IOR: f64 = 1.49;
/// Mitsuba's default `diffuse_reflectance`.
const DEFAULT_DIFFUSE: f64 = 0.5;

#[derive(Debug, Clone, PartialEq)]
pub struct Plastic {
    /// The base's albedo (a texture's mean where `diffuse_texture` is given).
    pub diffuse: DVec3,
    pub diffuse_texture: Option<Texture>,
    pub specular: DVec3,
    /// The index of refraction of the coating (inside) and of the medium above it.
    pub int_ior: f64,
    pub ext_ior: f64,
    /// Mitsuba's `nonlinear`: the internal reflections tint the base (1 - R fdr_int).
    pub nonlinear: bool,
}

impl Plastic {
    /// The relative index eta = int_ior / ext_ior.
    pub fn eta(&self) -> f64 {
        self.int_ior / self.ext_ior
    }

    /// The properties of a Mitsuba plastic's layers (its base and coating: `diffuse_reflectance`,
    /// `specular_reflectance`, `int_ior`, `ext_ior`, `nonlinear`) as TOML fields, for the smooth
    /// and the rough kind.
    pub(crate) fn mitsuba_layers(p: &mut dyn PluginProps) -> Vec<(&'static str, toml::Value)> {
        let mut fields = Vec::new();
        if let Some(d) = p.color_or_texture("diffuse_reflectance") {
            fields.push(("diffuse_reflectance", d));
        }
        if let Some(c) = p.color("specular_reflectance") {
            fields.push(("specular_reflectance", color_value(c)));
        }
        // A <float>, or a <string> naming a material of Mitsuba's table (`polypropylene`).
        for (name, default) in [("int_ior", DEFAULT_INT_IOR), ("ext_ior", DEFAULT_EXT_IOR)] {
            fields.push((name, toml::Value::Float(ior::from_mitsuba(p, name, default))));
        }
        if let Some((b, _)) = p.boolean("nonlinear") {
            fields.push(("nonlinear", toml::Value::Boolean(b)));
        }
        if let Some(at) = p.texture() {
            p.error(at, "", "a textured parameter other than diffuse_reflectance is not supported (give <rgb> or <float> values)".into());
        }
        fields
    }

    /// Mitsuba's `m_specular_sampling_weight`: the specular lobe's share of the two albedos'
    /// means (`Texture::mean()`: a colour's channel mean, a texture's own; 0.5 for a black
    /// material, whose weight does not matter).
    pub fn specular_sampling_weight(&self) -> f64 {
        let d = self.diffuse_texture.as_ref().map_or(self.diffuse.element_sum() / 3.0, Texture::mitsuba_mean);
        let s = self.specular.element_sum() / 3.0;
        if d + s > 0.0 {
            s / (d + s)
        } else {
            0.5
        }
    }

    /// The base's colour slot: its albedo, or the reference -(start + 1) of its texture's record
    /// in the BSDF data (texture.wgsl).
    pub(crate) fn diffuse_slot(&self, data: &mut BsdfData) -> glam::Vec3 {
        match &self.diffuse_texture {
            Some(t) => glam::Vec3::new(-(t.pack(data) as f32) - 1.0, 0.0, 0.0),
            None => self.diffuse.as_vec3(),
        }
    }
}

/// The diffuse Fresnel reflectance, the Fresnel reflectance of a dielectric of relative index
/// eta averaged over a cosine-weighted hemisphere of incidence: Mitsuba's
/// `fresnel_diffuse_reflectance`, the fit of Egan and Hilgeman (1973) for eta < 1 and of d'Eon
/// and Irving (2011) otherwise.
pub fn fresnel_diffuse_reflectance(eta: f64) -> f64 {
    let inv_eta = 1.0 / eta;
    if eta < 1.0 {
        0.0636 * inv_eta + eta * (eta * -1.4399 + 0.7099) + 0.6681
    } else {
        // Horner's scheme in 1 / eta.
        [0.919317, -3.4793, 6.75335, -7.80989, 4.98554, -1.36881].iter().rev().fold(0.0, |acc, c| acc * inv_eta + c)
    }
}

impl BsdfPlugin for Plastic {
    const TOML_NAME: &'static str = "plastic";
    const FIELDS: &'static [&'static str] = &["diffuse_reflectance", "specular_reflectance", "int_ior", "ext_ior", "nonlinear"];
    const MITSUBA_PLUGINS: &'static [&'static str] = &["plastic"];
    const IS_DELTA: bool = false;
    const HAS_DELTA_LOBE: bool = true;
    const SELECTS_LOBES: bool = true;
    const TEXTURE_SLOTS: &'static [usize] = &[0];

    fn from_fields(f: &mut Fields) -> Plastic {
        let (diffuse, diffuse_texture) =
            if f.has("diffuse_reflectance") { f.color_or_texture("diffuse_reflectance", DVec3::ZERO) } else { (DVec3::splat(DEFAULT_DIFFUSE), None) };
        let specular = if f.has("specular_reflectance") { f.color("specular_reflectance", DVec3::ZERO) } else { DVec3::ONE };
        let int_ior = ior::from_field(f, "int_ior", DEFAULT_INT_IOR);
        let ext_ior = ior::from_field(f, "ext_ior", DEFAULT_EXT_IOR);
        let nonlinear = f.boolean("nonlinear", false);
        if diffuse.max_element() > 1.0 {
            f.warn_material(format!("diffuse_reflectance = {:?} exceeds 1: the material is not energy conserving", diffuse.to_array()));
        }
        Plastic { diffuse, diffuse_texture, specular, int_ior, ext_ior, nonlinear }
    }

    fn from_mitsuba(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
        let fields = Plastic::mitsuba_layers(p);
        p.finish("diffuse_reflectance, specular_reflectance, int_ior, ext_ior, nonlinear");
        Some(fields)
    }

    fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        line("plastic.diffuse", vec3(self.diffuse));
        // Only a textured one adds a line: untextured scenes keep their hash.
        if let Some(t) = &self.diffuse_texture {
            line("plastic.diffuse.texture", t.hash_value(vec3));
        }
        line("plastic.specular", vec3(self.specular));
        line("plastic.int_ior", real(self.int_ior));
        line("plastic.ext_ior", real(self.ext_ior));
        line("plastic.nonlinear", self.nonlinear.to_string());
    }

    /// `p0 = (diffuse, eta)`, `p1 = (specular, specular_sampling_weight)`, `p2 = (fdr_int,
    /// nonlinear, 0, 0)`: the layout of WGSL's `plastic_of`.
    fn textures(&self) -> Vec<&Texture> {
        self.diffuse_texture.iter().collect()
    }

    fn pack(&self, data: &mut BsdfData) -> BsdfParams {
        let (d, s) = (self.diffuse_slot(data), self.specular.as_vec3());
        let fdr_int = fresnel_diffuse_reflectance(1.0 / self.eta());
        [
            [d.x, d.y, d.z, self.eta() as f32],
            [s.x, s.y, s.z, self.specular_sampling_weight() as f32],
            [fdr_int as f32, if self.nonlinear { 1.0 } else { 0.0 }, 0.0, 0.0],
            [0.0; 4],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fits against the diffuse Fresnel reflectance integrated numerically (2 ∫ F(cos) cos
    /// dcos over the hemisphere): within the accuracy their authors state (0.1% to 0.6% for the
    /// indices of real materials).
    #[test]
    fn the_diffuse_fresnel_fits_match_the_integral() {
        let fresnel = |cos_i: f64, eta: f64| super::super::fresnel::fresnel_dielectric(cos_i, eta).0;
        for eta in [1.0 / 1.5, 1.0 / 1.33, 1.33, 1.49, 1.5, 1.9] {
            let n = 200_000;
            let integral: f64 = (0..n).map(|i| {
                let c = (i as f64 + 0.5) / n as f64;
                2.0 * fresnel(c, eta) * c / n as f64
            }).sum();
            let fit = fresnel_diffuse_reflectance(eta);
            assert!((fit - integral).abs() <= 0.006 * integral + 1e-3, "eta {eta}: fit {fit}, integral {integral}");
        }
    }
}
