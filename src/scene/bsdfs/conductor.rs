//! Mitsuba's smooth `conductor` (WGSL: `shaders/bsdfs/conductor.wgsl`): a mirror, a delta
//! lobe, with the exact Fresnel term of a complex index eta + i k per channel, times
//! `specular_reflectance`. TOML `eta`, `k` (default 0 + 1i: F = 1, a perfect mirror, as
//! Mitsuba's `material="none"`) or `material`, one of Mitsuba's named conductors
//! (`named_conductors.rs`: "Au", "Cu", "Al", ...; not with `eta` or `k`), and
//! `specular_reflectance` (default 1). `eta`, `k` and `specular_reflectance` may each be a
//! texture, as in Mitsuba (colour slots 0, 1 and 2: the kernel looks them up at the hit).

use glam::DVec3;

use super::named_conductors::NAMED_CONDUCTORS;
use super::plugin::{color_value, BsdfData, BsdfParams, BsdfPlugin, Fields, PluginProps};
use crate::scene::hash::vec3;
use crate::scene::textures::Texture;

/// Fresnel reflection of a complex index of refraction; also the rough conductor's.
#[derive(Debug, Clone, PartialEq)]
pub struct Conductor {
    /// The complex index's real and imaginary parts (a texture's mean where `eta_texture`,
    /// `k_texture` are given).
    pub eta: DVec3,
    pub k: DVec3,
    pub eta_texture: Option<Texture>,
    pub k_texture: Option<Texture>,
    /// Mitsuba's specular_reflectance: a factor on the Fresnel term (a texture's mean where
    /// `reflectance_texture` is given).
    pub reflectance: DVec3,
    pub reflectance_texture: Option<Texture>,
}

impl Conductor {
    /// The complex index of Mitsuba's named conductor `name` (its spelling, case-sensitive).
    pub fn named(name: &str) -> Option<(DVec3, DVec3)> {
        NAMED_CONDUCTORS.iter().find(|(n, _, _)| *n == name).map(|&(_, eta, k)| (DVec3::from(eta), DVec3::from(k)))
    }

    /// What an unknown conductor name is told: every known name.
    fn unknown(name: &str) -> String {
        let known: Vec<&str> = NAMED_CONDUCTORS.iter().map(|(n, _, _)| *n).collect();
        format!("unknown conductor \"{name}\" (Mitsuba's named conductors: {}, or \"none\", a perfect mirror)", known.join(", "))
    }

    /// The fields both conductors read, in TOML: `material` (a named conductor) or `eta` and
    /// `k`, and `specular_reflectance`.
    pub(crate) fn read_fresnel(f: &mut Fields) -> Conductor {
        let (reflectance, reflectance_texture) = f.color_or_texture("specular_reflectance", DVec3::ONE);
        if let Some(m) = f.string("material") {
            for other in ["eta", "k"] {
                if f.has(other) {
                    f.error(m.span(), "material", format!("give either `material` or `eta` and `k`, not both (as Mitsuba requires)"));
                    break;
                }
            }
            let name = m.get_ref();
            let (eta, k) = match (name.as_str(), Conductor::named(name)) {
                ("none", _) => (DVec3::ZERO, DVec3::ONE),
                (_, Some(ek)) => ek,
                (_, None) => {
                    f.error(m.span(), "material", Conductor::unknown(name));
                    (DVec3::ZERO, DVec3::ONE)
                }
            };
            return Conductor { eta, k, eta_texture: None, k_texture: None, reflectance, reflectance_texture };
        }
        let (eta, eta_texture) = f.color_or_texture("eta", DVec3::ZERO);
        let (k, k_texture) = f.color_or_texture("k", DVec3::ONE);
        Conductor { eta, k, eta_texture, k_texture, reflectance, reflectance_texture }
    }

    /// The properties both conductors read, in Mitsuba XML, as TOML fields.
    pub(crate) fn mitsuba_fresnel(p: &mut dyn PluginProps) -> Vec<(&'static str, toml::Value)> {
        let reflectance = p.color_or_texture("specular_reflectance");
        // `eta` and `k` as <rgb> (unbounded, as Mitsuba's `get_unbounded_texture`) or textures.
        let index = |p: &mut dyn PluginProps, name: &str| if p.has_texture(name) { p.color_or_texture(name) } else { p.unbounded_color(name).map(color_value) };
        let eta = index(p, "eta");
        let k = index(p, "k");
        if let Some(at) = p.texture() {
            p.error(at, "", "a textured parameter other than eta, k, specular_reflectance (and a roughconductor's alpha) is not supported (give <rgb> or <float> values)".into());
        }
        let mut fields = Vec::new();
        match p.string("material") {
            // Mitsuba: a named material replaces eta and k, which may then not be given.
            Some((material, at)) if material != "none" => {
                if eta.is_some() || k.is_some() {
                    p.error(at, "material", "give either `material` or `eta` and `k`, not both (Mitsuba refuses both)".into());
                } else if Conductor::named(&material).is_none() {
                    p.error(at, "material", Conductor::unknown(&material));
                }
                fields.push(("material", toml::Value::String(material)));
            }
            _ => {
                fields.push(("eta", eta.unwrap_or_else(|| color_value([0.0; 3]))));
                fields.push(("k", k.unwrap_or_else(|| color_value([1.0; 3]))));
            }
        }
        if let Some(r) = reflectance {
            fields.push(("specular_reflectance", r));
        }
        fields
    }

    /// `conductor.eta`, `conductor.k`, `conductor.reflectance`.
    pub(crate) fn fresnel_hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        line("conductor.eta", vec3(self.eta));
        line("conductor.k", vec3(self.k));
        line("conductor.reflectance", vec3(self.reflectance));
        // Only a textured one adds a line: untextured scenes keep their hash.
        if let Some(t) = &self.reflectance_texture {
            line("conductor.reflectance.texture", t.hash_value(vec3));
        }
        if let Some(t) = &self.eta_texture {
            line("conductor.eta.texture", t.hash_value(vec3));
        }
        if let Some(t) = &self.k_texture {
            line("conductor.k.texture", t.hash_value(vec3));
        }
    }

    /// `p0 = (eta, alpha)`, `p1 = (k, distribution)` (its number), `p2 = (reflectance, 0)`:
    /// the layout of WGSL's `conductor_of`, with alpha 0 and Beckmann for the smooth one.
    /// A texture stands in its slot as the reference -(start + 1) of its record (texture.wgsl):
    /// eta's in p0, k's in p1, the reflectance's in p2.
    pub(crate) fn pack_with(&self, alpha: f32, distribution: super::distribution::Distribution, data: &mut BsdfData) -> BsdfParams {
        let mut slot = |texture: &Option<Texture>, value: DVec3| match texture {
            Some(t) => glam::Vec3::new(-(t.pack(data) as f32) - 1.0, 0.0, 0.0),
            None => value.as_vec3(),
        };
        let e = slot(&self.eta_texture, self.eta);
        let k = slot(&self.k_texture, self.k);
        let r = slot(&self.reflectance_texture, self.reflectance);
        [
            [e.x, e.y, e.z, alpha],
            [k.x, k.y, k.z, distribution.constant() as f32],
            [r.x, r.y, r.z, 0.0],
            [0.0; 4],
        ]
    }
}

impl Conductor {
    /// The textures of its Fresnel term and factor: eta's, k's, the reflectance's.
    pub(crate) fn fresnel_textures(&self) -> Vec<&Texture> {
        self.eta_texture.iter().chain(&self.k_texture).chain(&self.reflectance_texture).collect()
    }
}

impl BsdfPlugin for Conductor {
    const TOML_NAME: &'static str = "conductor";
    const FIELDS: &'static [&'static str] = &["eta", "k", "material", "specular_reflectance"];
    const MITSUBA_PLUGINS: &'static [&'static str] = &["conductor"];
    const IS_DELTA: bool = true;
    const TEXTURE_SLOTS: &'static [usize] = &[0, 1, 2];

    fn textures(&self) -> Vec<&Texture> {
        self.fresnel_textures()
    }

    fn from_fields(f: &mut Fields) -> Conductor {
        Conductor::read_fresnel(f)
    }

    fn from_mitsuba(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
        let fields = Conductor::mitsuba_fresnel(p);
        p.finish("eta, k, material, specular_reflectance");
        Some(fields)
    }

    fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        self.fresnel_hash_lines(line);
    }

    fn pack(&self, data: &mut BsdfData) -> BsdfParams {
        self.pack_with(0.0, super::distribution::Distribution::Beckmann, data)
    }
}
