//! Mitsuba's `principled` (WGSL: `shaders/bsdfs/principled.wgsl`): the Disney principled BRDF
//! (Burley 2012, 2015) as Mitsuba 3's `principled.cpp` and `principledhelpers.h` define it, term
//! for term. With M = `metallic`, C = `base_color`, r = `roughness`, the lobes (wo the viewer's
//! direction, wi the scattered one, h their half vector, all above the surface):
//!
//! - the main specular reflection, GGX of alpha = max(0.001, r^2), Smith's separable G, and a
//!   Fresnel term blending a dielectric's F(wo . h) (index eta) with Schlick's (metallic,
//!   tinted):
//!     F = (1 - M)(1 - spec_tint) F_dielectric + M Schlick(C) + (1 - M) spec_tint Schlick(c_tint R0(eta)),
//!     f = F D G / (4 cos_o cos_i), zero where F_dielectric is 0 (eta = 1: Mitsuba's mask);
//! - the clearcoat, GTR1 normals of alpha = lerp(0.1, 0.001, clearcoat_gloss), Schlick's F of
//!   R0 = 0.04, G of GGX's G1 at alpha 0.25: f = clearcoat / 4 Fcc Dcc Gcc, *without* Disney's
//!   1 / (4 cos_o cos_i) (Mitsuba 3.9.1's definition, kept: the tests compare with its images);
//! - the diffuse lobe with retro-reflection, Fo = (1 - cos_i)^5, Fi = (1 - cos_o)^5,
//!   Rr = 2 r (h . wi)^2:
//!     f = (1 - M) C / pi [(1 - Fi / 2)(1 - Fo / 2) + Rr (Fo + Fi + Fo Fi (Rr - 1))],
//!   with `flatness` blending in Hanrahan-Krueger's fake subsurface term;
//! - the sheen, f = sheen (1 - M) (1 - h . wi)^5 lerp(1, c_tint, sheen_tint), c_tint = C / lum(C).
//!
//! Its own sampling picks the diffuse lobe (cosine-weighted), the clearcoat (GTR1 normals) or
//! the main specular (GGX normals by `--microfacet-sampling`, visible normals as Mitsuba by
//! default) with probabilities proportional to (1 - M) `diffuse_reflectance_sampling_rate`,
//! clearcoat / 4 `clearcoat_sampling_rate` and `main_specular_sampling_rate`; a normal whose
//! reflection is not on the side of both directions is a lost sample, as in Mitsuba. One
//! sided: the back is black.
//!
//! TOML and Mitsuba: `base_color` (default 0.5, a colour or a texture), `roughness` (0.5),
//! `metallic`, `spec_tint`, `sheen`, `sheen_tint`, `clearcoat`, `clearcoat_gloss` (0; each a
//! number in [0, 1] or a texture), `specular` (0.5, eta = 2 / (1 - sqrt(0.08 specular)) - 1) or
//! `eta`, `flatness` (0), `anisotropic` (0; a number in [0, 1]: the main specular lobe's GGX
//! stretched along the surface's dp/du, Mitsuba's `calc_dist_params`), `spec_trans` (0 only:
//! transmission needs the dielectric's two-sided handling, not carried yet), and the three
//! sampling rates (1).

use glam::DVec3;

use super::plugin::{BsdfData, BsdfParams, BsdfPlugin, Fields, PluginProps};
use crate::scene::emitters::luminance;
use crate::scene::hash::{real, vec3};
use crate::scene::textures::Texture;

/// Mitsuba's `base_color`, `roughness` and `specular` when not given.
pub(super) const DEFAULT_BASE_COLOR: f64 = 0.5;
const DEFAULT_ROUGHNESS: f64 = 0.5;
const DEFAULT_SPECULAR: f64 = 0.5;

/// The weights that may be textures, in the order of their slots in the parameter block
/// (`WEIGHT_SLOTS`): roughness, then metallic … clearcoat_gloss.
const WEIGHTS: [&str; 7] = ["roughness", "metallic", "spec_tint", "sheen", "sheen_tint", "clearcoat", "clearcoat_gloss"];
/// Where each of `WEIGHTS` lives in the parameter block (slot, component).
const WEIGHT_SLOTS: [(usize, usize); 7] = [(0, 3), (1, 0), (1, 1), (1, 2), (1, 3), (2, 0), (2, 1)];
/// The scalar texture slots: the weights', then `anisotropic`'s (p2.z), then `spec_trans`'s
/// (p3.x).
const SCALAR_SLOTS: [(usize, usize); 9] = [WEIGHT_SLOTS[0], WEIGHT_SLOTS[1], WEIGHT_SLOTS[2], WEIGHT_SLOTS[3], WEIGHT_SLOTS[4], WEIGHT_SLOTS[5], WEIGHT_SLOTS[6], (2, 2), (3, 0)];
/// The numbers that must be constants: the fake subsurface blend and the sampling rates.
const RATES: [&str; 3] = ["main_specular_sampling_rate", "clearcoat_sampling_rate", "diffuse_reflectance_sampling_rate"];
/// Mitsuba's index of a principled BSDF that transmits: an index of 1 (or a `specular` of 0)
/// refracts nothing and is not plausible for transmission, so Mitsuba takes 1.001 (a `specular`
/// of 1e-3) instead.
fn transmissive_eta(eta: f64, from_specular: bool) -> f64 {
    match (eta == 1.0, from_specular) {
        (true, true) => eta_from_specular(1e-3),
        (true, false) => 1.001,
        (false, _) => eta,
    }
}

/// One of the principled BSDF's scalar parameters: a number, or a texture of it (Mitsuba's
/// `eval_1` at the hit; `value` is then its mean).
#[derive(Debug, Clone, PartialEq)]
pub struct Weight {
    pub value: f64,
    pub texture: Option<Texture>,
}

impl Weight {
    pub(super) fn constant(value: f64) -> Weight {
        Weight { value, texture: None }
    }

    /// Its number in the parameter block: the value, or -(start + 1) of its texture's record.
    pub(super) fn pack(&self, data: &mut BsdfData) -> f32 {
        match &self.texture {
            Some(t) => -(t.pack(data) as f32) - 1.0,
            None => self.value as f32,
        }
    }

    /// TOML field `name`: a texture table (read as Mitsuba's `eval_1`; `value` is its mean's
    /// luminance), a number checked by `problem`, or `default` where not given.
    pub(super) fn from_field(f: &mut Fields, name: &str, default: f64, problem: impl Fn(f64) -> Option<String>) -> Weight {
        if f.is_table(name) {
            let (_, t) = f.color_or_texture(name, DVec3::ZERO);
            let t = t.map(Texture::scalar);
            let value = t.as_ref().map_or(default, |t| luminance(t.mean()));
            return Weight { value, texture: t };
        }
        match f.number(name) {
            None => Weight::constant(default),
            Some(v) => {
                if let Some(problem) = problem(*v.get_ref()) {
                    f.error(v.span(), name, problem);
                }
                Weight::constant(*v.get_ref())
            }
        }
    }

    /// Mitsuba property `name` as a TOML field pushed to `fields`: a nested texture, or a float
    /// checked by `problem`; false where it was refused.
    pub(super) fn mitsuba_field(p: &mut dyn PluginProps, name: &'static str, problem: impl Fn(f64) -> Option<String>, fields: &mut Vec<(&'static str, toml::Value)>) -> bool {
        if p.has_texture(name) {
            if let Some(t) = p.color_or_texture(name) {
                fields.push((name, t));
            }
            return true;
        }
        match p.float(name) {
            Some((v, at)) => match problem(v) {
                Some(problem) => {
                    p.error(at, name, problem);
                    false
                }
                None => {
                    fields.push((name, toml::Value::Float(v)));
                    true
                }
            },
            None => true,
        }
    }

    pub(super) fn hash_value(&self) -> String {
        match &self.texture {
            None => real(self.value),
            Some(t) => format!("{} {}", real(self.value), t.hash_value(vec3)),
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Principled {
    /// C (a texture's mean where `base_color_texture` is given).
    pub base_color: DVec3,
    pub base_color_texture: Option<Texture>,
    /// roughness, metallic, spec_tint, sheen, sheen_tint, clearcoat, clearcoat_gloss.
    pub weights: [Weight; 7],
    /// The relative index of the dielectric Fresnel term (from `specular` or `eta`).
    pub eta: f64,
    /// The fake subsurface blend.
    pub flatness: f64,
    /// Mitsuba's `anisotropic` in [0, 1] (a number or a texture): the main specular lobe's GGX
    /// of alpha (max(0.001, r^2 / aspect), max(0.001, r^2 aspect)) along dp/du and across it,
    /// aspect = sqrt(1 - 0.9 anisotropic); 0: isotropic.
    pub anisotropic: Weight,
    /// Mitsuba's `spec_trans` in [0, 1] (a number or a texture): the weight of the rough
    /// dielectric transmission lobe; given other than the number 0 (Mitsuba's has_spec_trans),
    /// the material transmits and scatters on both sides.
    pub spec_trans: Weight,
    /// main_specular, clearcoat, diffuse_reflectance sampling rates.
    pub rates: [f64; 3],
}

/// Mitsuba's index from `specular`: eta = 2 / (1 - sqrt(0.08 specular)) - 1.
fn eta_from_specular(specular: f64) -> f64 {
    2.0 / (1.0 - (0.08 * specular).sqrt()) - 1.0
}

/// Why a weight's value is refused, if it is: every weight is a blend factor or strength in
/// [0, 1].
fn weight_problem(name: &str, v: f64) -> Option<String> {
    (!(0.0..=1.0).contains(&v)).then(|| format!("`{name}` of a principled BSDF must be in [0, 1] (got {v})"))
}

/// Why `specular` is refused: it must give a finite index >= 1, 0 <= specular < 12.5.
fn specular_problem(v: f64) -> Option<String> {
    (!(0.0..12.5).contains(&v)).then(|| format!("`specular` must be in [0, 12.5) (it gives eta = 2 / (1 - sqrt(0.08 specular)) - 1; got {v})"))
}

pub(super) fn eta_problem(v: f64) -> Option<String> {
    (!(v.is_finite() && v > 0.0)).then(|| format!("`eta` must be a finite number > 0 (got {v})"))
}

/// `base_color` from TOML fields: a colour or a texture (its mean the host's value), Mitsuba's
/// 0.5 where not given; a warning above 1.
pub(super) fn base_color_from_fields(f: &mut Fields) -> (DVec3, Option<Texture>) {
    let (base_color, texture) = if f.has("base_color") { f.color_or_texture("base_color", DVec3::ZERO) } else { (DVec3::splat(DEFAULT_BASE_COLOR), None) };
    if base_color.max_element() > 1.0 {
        f.warn_material(format!("base_color = {:?} exceeds 1: the material is not energy conserving", base_color.to_array()));
    }
    (base_color, texture)
}

/// `base_color` in a parameter block's colour slot: the colour, or its texture's reference
/// -(start + 1) in x.
pub(super) fn pack_base_color(base_color: DVec3, texture: &Option<Texture>, data: &mut BsdfData) -> glam::Vec3 {
    match texture {
        Some(t) => glam::Vec3::new(-(t.pack(data) as f32) - 1.0, 0.0, 0.0),
        None => base_color.as_vec3(),
    }
}

/// The sampling rates `names` from TOML fields, 1 where not given, each checked by
/// `rate_problem`.
pub(super) fn rates_from_fields<const N: usize>(f: &mut Fields, names: [&str; N]) -> [f64; N] {
    names.map(|name| match f.number(name) {
        None => 1.0,
        Some(v) => {
            if let Some(problem) = rate_problem(name, *v.get_ref()) {
                f.error(v.span(), name, problem);
            }
            *v.get_ref()
        }
    })
}

/// The sampling rates `names` of a Mitsuba plugin as TOML fields pushed to `fields`; false where
/// one was refused.
pub(super) fn mitsuba_rates(p: &mut dyn PluginProps, names: &[&'static str], fields: &mut Vec<(&'static str, toml::Value)>) -> bool {
    let mut ok = true;
    for &name in names {
        if let Some((v, at)) = p.float(name) {
            match rate_problem(name, v) {
                Some(problem) => {
                    p.error(at, name, problem);
                    ok = false;
                }
                None => fields.push((name, toml::Value::Float(v))),
            }
        }
    }
    ok
}

/// Why a sampling rate is refused: a lobe that its own sampling never picks is found only by
/// paths that end on a light, which would bias every other path (Mitsuba allows 0).
pub(super) fn rate_problem(name: &str, v: f64) -> Option<String> {
    (!(v.is_finite() && v > 0.0)).then(|| {
        format!("`{name}` must be a finite number > 0 (got {v}): a lobe its sampling never picks would be missed by every bounce that does not end on a light")
    })
}

/// A weight's default where not given: Mitsuba's roughness 0.5, every other 0 (the thin
/// principled BSDF's too).
pub(super) fn default_weight(name: &str) -> f64 {
    if name == "roughness" {
        DEFAULT_ROUGHNESS
    } else {
        0.0
    }
}

impl BsdfPlugin for Principled {
    const TOML_NAME: &'static str = "principled";
    const FIELDS: &'static [&'static str] = &[
        "base_color",
        "roughness",
        "metallic",
        "spec_tint",
        "sheen",
        "sheen_tint",
        "clearcoat",
        "clearcoat_gloss",
        "specular",
        "eta",
        "flatness",
        "anisotropic",
        "spec_trans",
        "main_specular_sampling_rate",
        "clearcoat_sampling_rate",
        "diffuse_reflectance_sampling_rate",
    ];
    const MITSUBA_PLUGINS: &'static [&'static str] = &["principled"];
    const IS_DELTA: bool = false;
    const MICROFACETS: bool = true;
    const TRANSMITS_BY_PARAMETERS: bool = true;
    const TEXTURE_SLOTS: &'static [usize] = &[0];
    const SCALAR_TEXTURE_SLOTS: &'static [(usize, usize)] = &SCALAR_SLOTS;

    /// Mitsuba's has_spec_trans: `spec_trans` given other than the number 0 (a texture that is 0
    /// somewhere still transmits: its back side is the dielectric's).
    fn transmits(&self) -> bool {
        self.spec_trans.texture.is_some() || self.spec_trans.value != 0.0
    }

    fn fields_transmit(fields: &[(&str, toml::Value)]) -> bool {
        fields.iter().any(|(k, v)| *k == "spec_trans" && (v.is_table() || v.as_float().is_some_and(|x| x != 0.0) || v.as_integer().is_some_and(|x| x != 0)))
    }

    fn from_fields(f: &mut Fields) -> Principled {
        let (base_color, base_color_texture) = base_color_from_fields(f);
        let weights = WEIGHTS.map(|name| Weight::from_field(f, name, default_weight(name), |v| weight_problem(name, v)));
        let from_specular = !f.has("eta");
        let eta = match (f.number("specular"), f.number("eta")) {
            (Some(_), Some(e)) => {
                f.error(e.span(), "eta", "give `eta` or `specular`, not both (each sets the index of the other; Mitsuba refuses both too)");
                1.5
            }
            (Some(s), None) => {
                if let Some(problem) = specular_problem(*s.get_ref()) {
                    f.error(s.span(), "specular", problem);
                }
                eta_from_specular(*s.get_ref())
            }
            (None, Some(e)) => {
                if let Some(problem) = eta_problem(*e.get_ref()) {
                    f.error(e.span(), "eta", problem);
                }
                *e.get_ref()
            }
            (None, None) => eta_from_specular(DEFAULT_SPECULAR),
        };
        // `anisotropic` and `spec_trans` may be textures (Mitsuba's eval_1 at the hit);
        // `flatness` is a number.
        let [flatness, anisotropic, spec_trans] = ["flatness", "anisotropic", "spec_trans"].map(|name| {
            if name == "flatness" && f.is_table(name) {
                let span = f.span_of(name);
                f.error(span, name, format!("a textured `{name}` is not supported: give a number in [0, 1]"));
                return Weight::constant(0.0);
            }
            Weight::from_field(f, name, 0.0, |v| weight_problem(name, v))
        });
        let flatness = flatness.value;
        // Mitsuba's has_spec_trans: `spec_trans` given other than the number 0.
        let transmits = spec_trans.texture.is_some() || spec_trans.value != 0.0;
        let eta = if transmits { transmissive_eta(eta, from_specular) } else { eta };
        let rates = rates_from_fields(f, RATES);
        Principled { base_color, base_color_texture, weights, eta, flatness, anisotropic, spec_trans, rates }
    }

    fn from_mitsuba(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
        let mut fields = Vec::new();
        let mut ok = true;
        if let Some(c) = p.color_or_texture("base_color") {
            fields.push(("base_color", c));
        }
        // A number in [0, 1], or a texture (its value at the hit, Mitsuba's eval_1).
        for name in WEIGHTS.into_iter().chain(["flatness", "anisotropic", "spec_trans"]) {
            if name == "flatness" && p.has_texture(name) {
                p.error(p.at(), name, format!("a textured `{name}` is not supported (give a <float>)"));
                let _ = p.color_or_texture(name);
                ok = false;
                continue;
            }
            ok &= Weight::mitsuba_field(p, name, |v| weight_problem(name, v), &mut fields);
        }
        match (p.float("specular"), p.float("eta")) {
            (Some(_), Some((_, at))) => {
                p.error(at, "eta", "give `eta` or `specular`, not both (Mitsuba refuses both too)".into());
                ok = false;
            }
            (Some((s, at)), None) => match specular_problem(s) {
                Some(problem) => {
                    p.error(at, "specular", problem);
                    ok = false;
                }
                None => fields.push(("specular", toml::Value::Float(s))),
            },
            (None, Some((e, at))) => match eta_problem(e) {
                Some(problem) => {
                    p.error(at, "eta", problem);
                    ok = false;
                }
                None => fields.push(("eta", toml::Value::Float(e))),
            },
            (None, None) => {}
        }
        ok &= mitsuba_rates(p, &RATES, &mut fields);
        p.finish(
            "base_color, roughness, metallic, spec_tint, sheen, sheen_tint, clearcoat, clearcoat_gloss, specular or eta, flatness, \
             anisotropic, spec_trans, main_specular_sampling_rate, clearcoat_sampling_rate, diffuse_reflectance_sampling_rate",
        );
        ok.then_some(fields)
    }

    fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        line("principled.base_color", vec3(self.base_color));
        if let Some(t) = &self.base_color_texture {
            line("principled.base_color.texture", t.hash_value(vec3));
        }
        for (name, w) in WEIGHTS.iter().zip(&self.weights) {
            line(&format!("principled.{name}"), w.hash_value());
        }
        line("principled.eta", real(self.eta));
        line("principled.flatness", real(self.flatness));
        // Only an anisotropic one adds a line: isotropic scenes keep their hash.
        if self.anisotropic.value != 0.0 || self.anisotropic.texture.is_some() {
            line("principled.anisotropic", self.anisotropic.hash_value());
        }
        line("principled.rates", self.rates.map(real).join(" "));
        // Only one that transmits adds a line: every other scene keeps its hash.
        if self.transmits() {
            line("principled.spec_trans", self.spec_trans.hash_value());
        }
    }

    fn textures(&self) -> Vec<&Texture> {
        self.base_color_texture.iter().chain(self.weights.iter().chain([&self.anisotropic, &self.spec_trans]).filter_map(|w| w.texture.as_ref())).collect()
    }

    /// `p0 = (base_color, roughness)`, `p1 = (metallic, spec_tint, sheen, sheen_tint)`, `p2 =
    /// (clearcoat, clearcoat_gloss, anisotropic, first BSDF datum)`: the layout of WGSL's
    /// `principled_of` (every number that may be a texture in the block, where the kernel
    /// resolves it); the data: flatness, the three sampling rates, eta.
    fn pack(&self, data: &mut BsdfData) -> BsdfParams {
        let c = pack_base_color(self.base_color, &self.base_color_texture, data);
        let w = self.weights.clone().map(|w| w.pack(data));
        let anisotropic = self.anisotropic.pack(data);
        let spec_trans = self.spec_trans.pack(data);
        let first = data.push(&[self.flatness as f32, self.rates[0] as f32, self.rates[1] as f32, self.rates[2] as f32, self.eta as f32]);
        [[c.x, c.y, c.z, w[0]], [w[1], w[2], w[3], w[4]], [w[5], w[6], anisotropic, first as f32], [spec_trans, if self.transmits() { 1.0 } else { 0.0 }, 0.0, 0.0]]
    }
}

impl Principled {
    /// Mitsuba's index from `specular`: eta = 2 / (1 - sqrt(0.08 specular)) - 1 (R0 = 0.08
    /// specular).
    pub fn eta_from_specular(specular: f64) -> f64 {
        eta_from_specular(specular)
    }

    /// Mitsuba's defaults: base colour 0.5, roughness 0.5, specular 0.5, every other weight 0.
    pub fn mitsuba_default() -> Principled {
        Principled {
            base_color: DVec3::splat(DEFAULT_BASE_COLOR),
            base_color_texture: None,
            weights: WEIGHTS.map(|name| Weight::constant(default_weight(name))),
            eta: eta_from_specular(DEFAULT_SPECULAR),
            flatness: 0.0,
            anisotropic: Weight::constant(0.0),
            spec_trans: Weight::constant(0.0),
            rates: [1.0; 3],
        }
    }

    /// The same material with weight `name` (one of roughness, metallic, spec_tint, sheen,
    /// sheen_tint, clearcoat, clearcoat_gloss) set to `value`.
    pub fn with(mut self, name: &str, value: f64) -> Principled {
        let k = WEIGHTS.iter().position(|w| *w == name).unwrap_or_else(|| panic!("no principled weight `{name}`"));
        self.weights[k] = Weight::constant(value);
        self
    }

    /// Weight `name`'s value (a texture's mean).
    pub fn weight(&self, name: &str) -> f64 {
        let k = WEIGHTS.iter().position(|w| *w == name).unwrap_or_else(|| panic!("no principled weight `{name}`"));
        self.weights[k].value
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Mitsuba's mapping: specular 0.5 is eta 1.5 (R0 = 0.04), specular 0 is eta 1.
    #[test]
    fn specular_maps_to_mitsubas_index() {
        assert!((eta_from_specular(0.5) - 1.5).abs() < 1e-12);
        assert_eq!(eta_from_specular(0.0), 1.0);
        // R0 = ((eta - 1) / (eta + 1))^2 = 0.08 specular.
        for s in [0.1, 0.5, 1.0, 5.0] {
            let eta = eta_from_specular(s);
            let r0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
            assert!((r0 - 0.08 * s).abs() < 1e-12, "specular {s}: R0 {r0}");
        }
    }
}
