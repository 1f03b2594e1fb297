//! Mitsuba's `principledthin` (WGSL: `shaders/bsdfs/principled_thin.wgsl`): the thin-surface
//! variant of the Disney principled BSDF (Burley 2015, section 5.2), as Mitsuba 3's
//! `principledthin.cpp` and `principledhelpers.h` define it, term for term. A sheet with no
//! inside: both sides scatter alike (wo is mirrored to the front), and light passing through is
//! not bent. With C = `base_color`, r = `roughness`, S = `spec_trans`, T = `diff_trans` / 2,
//! wo the viewer's direction, wi the scattered one, wi_r = wi mirrored to wo's side, h =
//! normalize(wo + wi_r):
//!
//! - specular reflection, S F_thin D G / (4 cos_o), GGX of alpha = max(0.001, r^2) (anisotropic:
//!   Mitsuba's `calc_dist_params`), F_thin = lerp(F_dielectric(wo . h, eta), Schlick(c_tint
//!   R0(eta)), spec_tint): no specular reflection at all where S = 0 (Mitsuba's definition);
//! - specular transmission, S C (1 - F_dielectric) D' G' / (4 cos_o), a reflection about h turned
//!   through the sheet, GGX of roughness scaled by (0.65 eta - 0.35) (Burley 2015, fig. 15);
//! - diffuse reflection with retro-reflection, `flatness` blending in the fake subsurface term,
//!   and the sheen, as the principled BSDF's, weighted by (1 - S)(1 - T);
//! - diffuse transmission, (1 - S) T C / pi.
//!
//! Its own sampling picks the specular reflection, the specular transmission, the cosine
//! hemisphere on wo's side or the one behind, with probabilities proportional to S / 2
//! `specular_reflectance_sampling_rate`, S / 2 `specular_transmittance_sampling_rate`, (1 - S)(1
//! - T) `diffuse_reflectance_sampling_rate` and (1 - S) T `diffuse_transmittance_sampling_rate`;
//! microfacet normals by `--microfacet-sampling`, and a normal whose reflection (or its turned
//! copy) is not on the side the lobe needs is a lost sample, as Mitsuba's mask.
//!
//! TOML (`bsdf = "principledthin"`) and Mitsuba: `base_color` (0.5, a colour or a texture),
//! `roughness` (0.5), `anisotropic`, `spec_trans`, `sheen`, `sheen_tint`, `flatness`,
//! `spec_tint` (0; each a number in [0, 1] or a texture), `diff_trans` (0; in [0, 2] or a
//! texture), `eta` (1.5, a number > 0), and the four sampling rates (1).

use glam::DVec3;

use super::plugin::{BsdfData, BsdfParams, BsdfPlugin, Fields, PluginProps};
use super::principled::{base_color_from_fields, default_weight, eta_problem, mitsuba_rates, pack_base_color, rates_from_fields, Weight, DEFAULT_BASE_COLOR};
use crate::scene::hash::{real, vec3};
use crate::scene::textures::Texture;

/// Mitsuba's `eta` where not given (the other defaults are the principled BSDF's).
const DEFAULT_ETA: f64 = 1.5;

/// The numbers that may be textures, in the order of `WEIGHT_SLOTS`, with their largest value
/// (`diff_trans` runs to 2: Mitsuba halves it).
const WEIGHTS: [(&str, f64); 8] = [
    ("roughness", 1.0),
    ("anisotropic", 1.0),
    ("spec_trans", 1.0),
    ("sheen", 1.0),
    ("sheen_tint", 1.0),
    ("flatness", 1.0),
    ("spec_tint", 1.0),
    ("diff_trans", 2.0),
];
/// Where each of `WEIGHTS` lives in the parameter block (slot, component): the layout WGSL's
/// `principled_thin_of` reads.
const WEIGHT_SLOTS: [(usize, usize); 8] = [(0, 3), (1, 0), (1, 1), (1, 2), (1, 3), (2, 0), (2, 1), (2, 2)];
/// The sampling rates, in the order of the BSDF data.
const RATES: [&str; 4] = [
    "specular_reflectance_sampling_rate",
    "specular_transmittance_sampling_rate",
    "diffuse_reflectance_sampling_rate",
    "diffuse_transmittance_sampling_rate",
];

#[derive(Debug, Clone, PartialEq)]
pub struct PrincipledThin {
    /// C (a texture's mean where `base_color_texture` is given).
    pub base_color: DVec3,
    pub base_color_texture: Option<Texture>,
    /// roughness, anisotropic, spec_trans, sheen, sheen_tint, flatness, spec_tint, diff_trans
    /// (Mitsuba's, in [0, 2]).
    pub weights: [Weight; 8],
    /// The sheet's relative index (its Fresnel terms and the transmission's roughness scale).
    pub eta: f64,
    /// specular reflectance, specular transmittance, diffuse reflectance, diffuse transmittance
    /// sampling rates.
    pub rates: [f64; 4],
}

fn weight_problem(name: &str, max: f64, v: f64) -> Option<String> {
    (!(0.0..=max).contains(&v)).then(|| format!("`{name}` of a principledthin BSDF must be in [0, {max}] (got {v})"))
}

impl BsdfPlugin for PrincipledThin {
    const TOML_NAME: &'static str = "principledthin";
    const FIELDS: &'static [&'static str] = &[
        "base_color",
        "roughness",
        "anisotropic",
        "spec_trans",
        "sheen",
        "sheen_tint",
        "flatness",
        "spec_tint",
        "diff_trans",
        "eta",
        "specular_reflectance_sampling_rate",
        "specular_transmittance_sampling_rate",
        "diffuse_reflectance_sampling_rate",
        "diffuse_transmittance_sampling_rate",
    ];
    const MITSUBA_PLUGINS: &'static [&'static str] = &["principledthin"];
    const IS_DELTA: bool = false;
    const MICROFACETS: bool = true;
    const TRANSMITS: bool = true;
    const BOTH_SIDES: bool = true;
    const TEXTURE_SLOTS: &'static [usize] = &[0];
    const SCALAR_TEXTURE_SLOTS: &'static [(usize, usize)] = &WEIGHT_SLOTS;

    fn from_fields(f: &mut Fields) -> PrincipledThin {
        let (base_color, base_color_texture) = base_color_from_fields(f);
        let weights = WEIGHTS.map(|(name, max)| Weight::from_field(f, name, default_weight(name), |v| weight_problem(name, max, v)));
        let eta = if f.is_table("eta") {
            let span = f.span_of("eta");
            f.error(span, "eta", "a textured `eta` is not supported: give a number > 0");
            DEFAULT_ETA
        } else {
            match f.number("eta") {
                None => DEFAULT_ETA,
                Some(e) => {
                    if let Some(problem) = eta_problem(*e.get_ref()) {
                        f.error(e.span(), "eta", problem);
                    }
                    *e.get_ref()
                }
            }
        };
        let rates = rates_from_fields(f, RATES);
        PrincipledThin { base_color, base_color_texture, weights, eta, rates }
    }

    fn from_mitsuba(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
        let mut fields = Vec::new();
        let mut ok = true;
        if let Some(c) = p.color_or_texture("base_color") {
            fields.push(("base_color", c));
        }
        for (name, max) in WEIGHTS {
            ok &= Weight::mitsuba_field(p, name, |v| weight_problem(name, max, v), &mut fields);
        }
        if p.has_texture("eta") {
            p.error(p.at(), "eta", "a textured `eta` is not supported (give a <float>)".into());
            let _ = p.take("eta");
            ok = false;
        } else if let Some((e, at)) = p.float("eta") {
            match eta_problem(e) {
                Some(problem) => {
                    p.error(at, "eta", problem);
                    ok = false;
                }
                None => fields.push(("eta", toml::Value::Float(e))),
            }
        }
        ok &= mitsuba_rates(p, &RATES, &mut fields);
        p.finish(
            "base_color, roughness, anisotropic, spec_trans, sheen, sheen_tint, flatness, spec_tint, diff_trans, eta, \
             specular_reflectance_sampling_rate, specular_transmittance_sampling_rate, diffuse_reflectance_sampling_rate, \
             diffuse_transmittance_sampling_rate",
        );
        ok.then_some(fields)
    }

    fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        line("principledthin.base_color", vec3(self.base_color));
        if let Some(t) = &self.base_color_texture {
            line("principledthin.base_color.texture", t.hash_value(vec3));
        }
        for ((name, _), w) in WEIGHTS.iter().zip(&self.weights) {
            line(&format!("principledthin.{name}"), w.hash_value());
        }
        line("principledthin.eta", real(self.eta));
        line("principledthin.rates", self.rates.map(real).join(" "));
    }

    fn textures(&self) -> Vec<&Texture> {
        self.base_color_texture.iter().chain(self.weights.iter().filter_map(|w| w.texture.as_ref())).collect()
    }

    /// `p0 = (base_color, roughness)`, `p1 = (anisotropic, spec_trans, sheen, sheen_tint)`, `p2 =
    /// (flatness, spec_tint, diff_trans, first BSDF datum)`: the layout of WGSL's
    /// `principled_thin_of` (every number that may be a texture in the block, where the kernel
    /// resolves it); the data: eta, then the four sampling rates.
    fn pack(&self, data: &mut BsdfData) -> BsdfParams {
        let c = pack_base_color(self.base_color, &self.base_color_texture, data);
        let w = self.weights.clone().map(|w| w.pack(data));
        let first = data.push(&[self.eta as f32, self.rates[0] as f32, self.rates[1] as f32, self.rates[2] as f32, self.rates[3] as f32]);
        [[c.x, c.y, c.z, w[0]], [w[1], w[2], w[3], w[4]], [w[5], w[6], w[7], first as f32], [0.0; 4]]
    }
}

impl PrincipledThin {
    /// Mitsuba's defaults: base colour 0.5, roughness 0.5, eta 1.5, every other weight 0 (a
    /// rough diffuse sheet: no specular lobe, nothing transmitted).
    pub fn mitsuba_default() -> PrincipledThin {
        PrincipledThin {
            base_color: DVec3::splat(DEFAULT_BASE_COLOR),
            base_color_texture: None,
            weights: WEIGHTS.map(|(name, _)| Weight::constant(default_weight(name))),
            eta: DEFAULT_ETA,
            rates: [1.0; 4],
        }
    }

    /// The same material with weight `name` (one of roughness, anisotropic, spec_trans, sheen,
    /// sheen_tint, flatness, spec_tint, diff_trans) set to `value`.
    pub fn with(mut self, name: &str, value: f64) -> PrincipledThin {
        let k = WEIGHTS.iter().position(|(w, _)| *w == name).unwrap_or_else(|| panic!("no principledthin weight `{name}`"));
        self.weights[k] = Weight::constant(value);
        self
    }

    /// Weight `name`'s value (a texture's mean).
    pub fn weight(&self, name: &str) -> f64 {
        let k = WEIGHTS.iter().position(|(w, _)| *w == name).unwrap_or_else(|| panic!("no principledthin weight `{name}`"));
        self.weights[k].value
    }

    /// Whether its roughness differs along dp/du and across it (`anisotropic` above 0 somewhere).
    pub fn is_anisotropic(&self) -> bool {
        let a = &self.weights[1];
        a.value > 0.0 || a.texture.is_some()
    }
}
