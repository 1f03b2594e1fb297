//! Mitsuba's smooth `dielectric` (WGSL: `shaders/bsdfs/dielectric.wgsl`): an interface between
//! two indices of refraction (numbers, or names of Mitsuba's table: `ior.rs`), reflecting with
//! the Fresnel term of unpolarised light and refracting the rest (two delta lobes, sampled with the Fresnel term as their probabilities,
//! whatever the pipeline's BSDF strategy). TOML and Mitsuba `int_ior` (default 1.5046, Mitsuba's
//! `bk7`), `ext_ior` (default 1.000277, `air`), `specular_reflectance` and
//! `specular_transmittance` (factors on the two lobes, default 1). Both sides scatter: the
//! inside of a closed surface is the denser medium.

use glam::DVec3;

use super::ior;
use super::plugin::{color_value, BsdfParams, BsdfPlugin, Fields, PluginProps};
use crate::scene::hash::{real, vec3};

/// Mitsuba's default interior index (`bk7`, borosilicate glass).
const DEFAULT_INT_IOR: f64 = 1.5046;
/// Mitsuba's default exterior index (`air`).
const DEFAULT_EXT_IOR: f64 = 1.000277;

#[derive(Debug, Clone, PartialEq)]
pub struct Dielectric {
    /// The index of refraction inside (against the surface normal) and outside.
    pub int_ior: f64,
    pub ext_ior: f64,
    /// Factors on the reflected and the refracted lobe (1: lossless).
    pub reflectance: DVec3,
    pub transmittance: DVec3,
}

impl Dielectric {
    /// The relative index eta = int_ior / ext_ior.
    pub fn eta(&self) -> f64 {
        self.int_ior / self.ext_ior
    }
}

impl BsdfPlugin for Dielectric {
    const TOML_NAME: &'static str = "dielectric";
    const FIELDS: &'static [&'static str] = &["int_ior", "ext_ior", "specular_reflectance", "specular_transmittance"];
    const MITSUBA_PLUGINS: &'static [&'static str] = &["dielectric"];
    const IS_DELTA: bool = true;
    const TRANSMITS: bool = true;
    const BOTH_SIDES: bool = true;

    fn from_fields(f: &mut Fields) -> Dielectric {
        let int_ior = ior::from_field(f, "int_ior", DEFAULT_INT_IOR);
        let ext_ior = ior::from_field(f, "ext_ior", DEFAULT_EXT_IOR);
        Dielectric {
            int_ior,
            ext_ior,
            reflectance: f.color("specular_reflectance", DVec3::ONE),
            transmittance: f.color("specular_transmittance", DVec3::ONE),
        }
    }

    fn from_mitsuba(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
        if let Some(at) = p.texture() {
            p.error(at, "", "a textured parameter is not supported (give <rgb> or <float> values)".into());
        }
        // A <float>, or a <string> naming a material of Mitsuba's table (`bk7`).
        let mut fields = Vec::new();
        for (name, default) in [("int_ior", DEFAULT_INT_IOR), ("ext_ior", DEFAULT_EXT_IOR)] {
            fields.push((name, toml::Value::Float(ior::from_mitsuba(p, name, default))));
        }
        for name in ["specular_reflectance", "specular_transmittance"] {
            if let Some(c) = p.color(name) {
                fields.push((name, color_value(c)));
            }
        }
        p.finish("int_ior, ext_ior, specular_reflectance, specular_transmittance");
        Some(fields)
    }

    fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        line("dielectric.int_ior", real(self.int_ior));
        line("dielectric.ext_ior", real(self.ext_ior));
        line("dielectric.reflectance", vec3(self.reflectance));
        line("dielectric.transmittance", vec3(self.transmittance));
    }

    /// `p0 = (reflectance, eta)`, `p1 = (transmittance, 0)`: the layout of WGSL's
    /// `dielectric_of`.
    fn pack(&self) -> BsdfParams {
        let (r, t) = (self.reflectance.as_vec3(), self.transmittance.as_vec3());
        [[r.x, r.y, r.z, self.eta() as f32], [t.x, t.y, t.z, 0.0], [0.0; 4]]
    }
}
