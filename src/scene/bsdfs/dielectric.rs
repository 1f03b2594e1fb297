//! Mitsuba's smooth `dielectric` (WGSL: `shaders/bsdfs/dielectric.wgsl`): an interface between
//! two indices of refraction (numbers, or names of Mitsuba's table: `ior.rs`), reflecting with
//! the Fresnel term of unpolarised light and refracting the rest (two delta lobes, sampled with the Fresnel term as their probabilities,
//! whatever the pipeline's BSDF strategy). TOML and Mitsuba `int_ior` (default 1.5046, Mitsuba's
//! `bk7`), `ext_ior` (default 1.000277, `air`), `specular_reflectance` and
//! `specular_transmittance` (factors on the two lobes, default 1; colours or textures,
//! `ior::InterfaceTextures`). Both sides scatter: the
//! inside of a closed surface is the denser medium.

use glam::DVec3;

use super::ior::{Interface, InterfaceTextures, INTERFACE_FIELDS};
use super::plugin::{BsdfData, BsdfParams, BsdfPlugin, Fields, PluginProps};
use crate::scene::hash::{real, vec3};

#[derive(Debug, Clone, PartialEq)]
pub struct Dielectric {
    /// The index of refraction inside (against the surface normal) and outside.
    pub int_ior: f64,
    pub ext_ior: f64,
    /// Factors on the reflected and the refracted lobe (1: lossless).
    pub reflectance: DVec3,
    pub transmittance: DVec3,
    /// Textures of the two factors, where given.
    pub textures: InterfaceTextures,
}

impl Dielectric {
    /// The relative index eta = int_ior / ext_ior.
    pub fn eta(&self) -> f64 {
        self.int_ior / self.ext_ior
    }
}

impl BsdfPlugin for Dielectric {
    const TOML_NAME: &'static str = "dielectric";
    const FIELDS: &'static [&'static str] = &INTERFACE_FIELDS;
    const MITSUBA_PLUGINS: &'static [&'static str] = &["dielectric"];
    const IS_DELTA: bool = true;
    const TRANSMITS: bool = true;
    const BOTH_SIDES: bool = true;
    const TEXTURE_SLOTS: &'static [usize] = &InterfaceTextures::SLOTS;

    fn textures(&self) -> Vec<&crate::scene::Texture> {
        self.textures.all()
    }

    fn from_fields(f: &mut Fields) -> Dielectric {
        let Interface { int_ior, ext_ior, reflectance, transmittance, textures } = Interface::from_fields(f);
        Dielectric { int_ior, ext_ior, reflectance, transmittance, textures }
    }

    fn from_mitsuba(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
        let fields = Interface::mitsuba_fields(p);
        p.finish("int_ior, ext_ior, specular_reflectance, specular_transmittance");
        Some(fields)
    }

    fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        line("dielectric.int_ior", real(self.int_ior));
        line("dielectric.ext_ior", real(self.ext_ior));
        line("dielectric.reflectance", vec3(self.reflectance));
        line("dielectric.transmittance", vec3(self.transmittance));
        self.textures.hash_lines("dielectric", line);
    }

    /// `p0 = (reflectance, eta)`, `p1 = (transmittance, 0)`: the layout of WGSL's
    /// `dielectric_of`.
    fn pack(&self, data: &mut BsdfData) -> BsdfParams {
        let [r, t] = self.textures.pack(self.reflectance, self.transmittance, data);
        [[r.x, r.y, r.z, self.eta() as f32], [t.x, t.y, t.z, 0.0], [0.0; 4], [0.0; 4]]
    }
}
