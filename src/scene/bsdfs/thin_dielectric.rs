//! Mitsuba's `thindielectric` (WGSL: `shaders/bsdfs/thin_dielectric.wgsl`): a thin pane of glass
//! (a window, a soap film) modelled as two parallel interfaces of relative index eta = int_ior /
//! ext_ior infinitely close together. Light reflects in the mirror direction with the Fresnel
//! reflectance R' = R + T R T + T R^3 T + ... = 2 R / (1 + R) of all the internal reflections
//! summed (R = F(|cos_i|)), or passes straight through with 1 - R' (no refraction: the two
//! bends cancel). Two delta lobes, picked with these probabilities; both sides alike. TOML and
//! Mitsuba `int_ior` (default bk7, 1.5046), `ext_ior` (default air, 1.000277), each a number or
//! a name of `ior.rs`, `specular_reflectance` and `specular_transmittance` (factors on the two
//! lobes, default 1).
//!
//! Index-matched (int_ior = ext_ior: R = 0) it is a pass-through, and so pathlab reads Mitsuba's
//! two null-flagged plugins: `null` (everything passes, weight 1) and `polarizer` as Mitsuba's
//! RGB variants render it (polarizer.cpp's unpolarised branch: everything passes with weight
//! 0.5 `transmittance`, whatever its angle `theta`; a warning says polarisation is not
//! modelled). As there, the surface is a vertex of the path (it counts towards `max_depth`),
//! next event estimation skips it (a delta) and shadow rays do not pass it (Mitsuba's `path`:
//! `ray_test` sees every shape). The reflected lobe's factor is 0, so a lobe choice at u = 0
//! exactly (R' = 0 >= u) ends the path rather than mirror it.

use glam::DVec3;

use super::ior::{Interface, InterfaceTextures, INTERFACE_FIELDS};
use super::plugin::{color_value, BsdfData, BsdfParams, BsdfPlugin, Fields, PluginProps};
use crate::scene::hash::{real, vec3};

#[derive(Debug, Clone, PartialEq)]
pub struct ThinDielectric {
    pub int_ior: f64,
    pub ext_ior: f64,
    /// Factors on the reflected and the transmitted lobe (1: lossless).
    pub reflectance: DVec3,
    pub transmittance: DVec3,
    /// Textures of the two factors, where given.
    pub textures: InterfaceTextures,
}

impl ThinDielectric {
    /// The relative index eta = int_ior / ext_ior.
    pub fn eta(&self) -> f64 {
        self.int_ior / self.ext_ior
    }
}

/// An index-matched pane passing `transmittance` (grey, or per channel) of the light, reflecting
/// none: the TOML fields of Mitsuba's `null` and `polarizer`.
fn pass_through_of(transmittance: toml::Value) -> Vec<(&'static str, toml::Value)> {
    vec![
        ("int_ior", toml::Value::Float(1.0)),
        ("ext_ior", toml::Value::Float(1.0)),
        ("specular_reflectance", toml::Value::Float(0.0)),
        ("specular_transmittance", transmittance),
    ]
}

fn pass_through(transmittance: f64) -> Vec<(&'static str, toml::Value)> {
    pass_through_of(toml::Value::Float(transmittance))
}

/// Mitsuba's `polarizer` in an RGB variant: `0.5 transmittance` passes (a colour, default 1);
/// `theta` (its angle, any type) and `polarizing` change nothing there and are taken, with one
/// warning that polarisation is not modelled.
fn polarizer(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
    let at = p.at();
    if p.has_texture("transmittance") {
        p.error(at, "transmittance", "a textured `transmittance` of <bsdf type=\"polarizer\"> is not supported (give an <rgb> or a <float>)".into());
        let _ = p.color_or_texture("transmittance");
        p.finish("transmittance, theta, polarizing");
        return None;
    }
    let t = p.color("transmittance").unwrap_or([1.0; 3]);
    let _ = p.take("theta");
    let _ = p.boolean("polarizing");
    p.warn(
        at,
        "",
        "a polarizer is rendered as Mitsuba's RGB variants render it: an unpolarised filter passing half the light (times `transmittance`) whatever its angle `theta`; polarisation (crossed polarizers extinguishing light) is not modelled".into(),
    );
    p.finish("transmittance, theta, polarizing");
    Some(pass_through_of(color_value(t.map(|c| 0.5 * c))))
}

impl BsdfPlugin for ThinDielectric {
    const TOML_NAME: &'static str = "thindielectric";
    const FIELDS: &'static [&'static str] = &INTERFACE_FIELDS;
    const MITSUBA_PLUGINS: &'static [&'static str] = &["thindielectric", "null", "polarizer"];
    const IS_DELTA: bool = true;
    const TRANSMITS: bool = true;
    const BOTH_SIDES: bool = true;
    const TEXTURE_SLOTS: &'static [usize] = &InterfaceTextures::SLOTS;

    fn textures(&self) -> Vec<&crate::scene::Texture> {
        self.textures.all()
    }

    fn from_fields(f: &mut Fields) -> ThinDielectric {
        let Interface { int_ior, ext_ior, reflectance, transmittance, textures } = Interface::from_fields(f);
        ThinDielectric { int_ior, ext_ior, reflectance, transmittance, textures }
    }

    fn from_mitsuba(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
        match p.plugin() {
            "null" => {
                p.finish("no parameters");
                return Some(pass_through(1.0));
            }
            "polarizer" => return polarizer(p),
            _ => {}
        }
        let fields = Interface::mitsuba_fields(p);
        p.finish("int_ior, ext_ior, specular_reflectance, specular_transmittance");
        Some(fields)
    }

    fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        line("thindielectric.int_ior", real(self.int_ior));
        line("thindielectric.ext_ior", real(self.ext_ior));
        line("thindielectric.reflectance", vec3(self.reflectance));
        line("thindielectric.transmittance", vec3(self.transmittance));
        self.textures.hash_lines("thindielectric", line);
    }

    /// `p0 = (reflectance, eta)`, `p1 = (transmittance, 0)`: the layout of WGSL's
    /// `thin_dielectric_of`.
    fn pack(&self, data: &mut BsdfData) -> BsdfParams {
        let [r, t] = self.textures.pack(self.reflectance, self.transmittance, data);
        [[r.x, r.y, r.z, self.eta() as f32], [t.x, t.y, t.z, 0.0], [0.0; 4], [0.0; 4]]
    }
}
