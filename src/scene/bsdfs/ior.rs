//! Named indices of refraction: Mitsuba 3's table (`include/mitsuba/render/ior.h`, values from
//! Hecht's Optics, measured at ~589 nm between 0 and 20 °C), so that `int_ior = "bk7"` in TOML
//! and `<string name="int_ior" value="bk7"/>` in Mitsuba's XML mean what they mean there. Names
//! are matched case-insensitively, as Mitsuba lower-cases them. Also what every dielectric
//! interface reads (`Interface`: the two indices and the factors on its two lobes).

use glam::DVec3;

use super::plugin::{Fields, PluginProps};
use crate::scene::Texture;

/// Mitsuba's default interior index of its dielectrics (`bk7`, borosilicate glass).
pub(crate) const DEFAULT_INT_IOR: f64 = 1.5046;
/// Mitsuba's default exterior index (`air`).
pub(crate) const DEFAULT_EXT_IOR: f64 = 1.000277;

/// Mitsuba's `ior_data`, in its order.
pub const NAMED_IORS: [(&str, f64); 23] = [
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

/// The index named `name` (any case).
pub fn lookup(name: &str) -> Option<f64> {
    let lower = name.to_lowercase();
    NAMED_IORS.iter().find(|(n, _)| *n == lower).map(|&(_, v)| v)
}

/// What an unknown name is told: every known name.
fn unknown(name: &str) -> String {
    let known: Vec<&str> = NAMED_IORS.iter().map(|(n, _)| *n).collect();
    format!("unknown index of refraction \"{name}\" (known: {})", known.join(", "))
}

/// An index of refraction from a TOML material's field: a number > 0 or a name of the table,
/// `default` when not given (or refused, with the error naming the field).
pub(crate) fn from_field(f: &mut Fields, name: &str, default: f64) -> f64 {
    let Some(v) = f.number_or_string(name) else { return default };
    match v.get_ref() {
        Ok(x) if *x > 0.0 => *x,
        Ok(x) => {
            f.error(v.span(), name, format!("`{name}` must be an index of refraction > 0 or a material's name (got {x})"));
            default
        }
        Err(s) => lookup(s).unwrap_or_else(|| {
            f.error(v.span(), name, unknown(s));
            default
        }),
    }
}

/// An index of refraction from a Mitsuba plugin's property: a `<float>` > 0 or a `<string>`
/// naming a material of the table (Mitsuba's `lookup_ior`), `default` when not given.
pub(crate) fn from_mitsuba(p: &mut dyn PluginProps, name: &str, default: f64) -> f64 {
    let Some((v, at)) = p.float_or_string(name) else { return default };
    let plugin = p.plugin().to_string();
    match v {
        Ok(x) if x.is_finite() && x > 0.0 => x,
        Ok(x) => {
            p.error(at, name, format!("`{name}` of <bsdf type=\"{plugin}\"> must be a finite index of refraction > 0 (got {x})"));
            default
        }
        Err(s) => lookup(&s).unwrap_or_else(|| {
            p.error(at, name, format!("`{name}` of <bsdf type=\"{plugin}\">: {}", unknown(&s)));
            default
        }),
    }
}

/// What every dielectric interface reads (Mitsuba's `dielectric`, `thindielectric` and
/// `roughdielectric`): the two indices (bk7 in air by default) and the factors on its reflected
/// and transmitted lobes (default 1).
pub(crate) struct Interface {
    pub int_ior: f64,
    pub ext_ior: f64,
    /// The factors, or their textures' means where `textures` gives them.
    pub reflectance: DVec3,
    pub transmittance: DVec3,
    /// Textures of the reflectance and the transmittance (Mitsuba's are textures).
    pub textures: InterfaceTextures,
}

/// The textures of an interface's two factors, where given: the kinds' colour slots 0 and 1
/// (p0.xyz the reflectance, p1.xyz the transmittance).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct InterfaceTextures {
    pub reflectance: Option<Texture>,
    pub transmittance: Option<Texture>,
}

impl InterfaceTextures {
    /// The colour slots of both factors.
    pub(crate) const SLOTS: [usize; 2] = [0, 1];

    pub(crate) fn all(&self) -> Vec<&Texture> {
        self.reflectance.iter().chain(&self.transmittance).collect()
    }

    /// The factors as packed: each its value, or the reference -(start + 1) of its texture's
    /// record (texture.wgsl).
    pub(crate) fn pack(&self, reflectance: DVec3, transmittance: DVec3, data: &mut super::plugin::BsdfData) -> [glam::Vec3; 2] {
        let mut slot = |t: &Option<Texture>, v: DVec3| match t {
            Some(t) => glam::Vec3::new(-(t.pack(data) as f32) - 1.0, 0.0, 0.0),
            None => v.as_vec3(),
        };
        [slot(&self.reflectance, reflectance), slot(&self.transmittance, transmittance)]
    }

    /// Lines of the scene hash, only where textured (untextured scenes keep their hash).
    pub(crate) fn hash_lines(&self, kind: &str, line: &mut dyn FnMut(&str, String)) {
        for (name, t) in [("reflectance", &self.reflectance), ("transmittance", &self.transmittance)] {
            if let Some(t) = t {
                line(&format!("{kind}.{name}.texture"), t.hash_value(crate::scene::hash::vec3));
            }
        }
    }
}

/// The fields of `Interface` in TOML and as Mitsuba's properties.
pub(crate) const INTERFACE_FIELDS: [&str; 4] = ["int_ior", "ext_ior", "specular_reflectance", "specular_transmittance"];

impl Interface {
    /// From a TOML material's fields.
    pub(crate) fn from_fields(f: &mut Fields) -> Interface {
        let (reflectance, r) = f.color_or_texture("specular_reflectance", DVec3::ONE);
        let (transmittance, t) = f.color_or_texture("specular_transmittance", DVec3::ONE);
        Interface {
            int_ior: from_field(f, "int_ior", DEFAULT_INT_IOR),
            ext_ior: from_field(f, "ext_ior", DEFAULT_EXT_IOR),
            reflectance,
            transmittance,
            textures: InterfaceTextures { reflectance: r, transmittance: t },
        }
    }

    /// A Mitsuba plugin's properties as the TOML fields (the factors colours or textures, other
    /// textures refused; the indices a <float> or a <string> naming a material of the table).
    /// The caller finishes the plugin.
    pub(crate) fn mitsuba_fields(p: &mut dyn PluginProps) -> Vec<(&'static str, toml::Value)> {
        let mut fields = Vec::new();
        for name in ["specular_reflectance", "specular_transmittance"] {
            if let Some(c) = p.color_or_texture(name) {
                fields.push((name, c));
            }
        }
        if let Some(at) = p.texture() {
            p.error(at, "", "a textured parameter other than specular_reflectance and specular_transmittance (and a roughdielectric's alpha) is not supported (give <rgb> or <float> values)".into());
        }
        for (name, default) in [("int_ior", DEFAULT_INT_IOR), ("ext_ior", DEFAULT_EXT_IOR)] {
            fields.push((name, toml::Value::Float(from_mitsuba(p, name, default))));
        }
        fields
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_found_in_any_case_and_defaults_are_mitsubas() {
        assert_eq!(lookup("BK7"), Some(1.5046));
        assert_eq!(lookup("acrylic glass"), Some(1.49));
        assert_eq!(lookup("polypropylene"), Some(1.49));
        assert_eq!(lookup("air"), Some(1.000277));
        assert_eq!(lookup("unobtainium"), None);
        assert!(unknown("x").contains("diamond"));
    }
}
