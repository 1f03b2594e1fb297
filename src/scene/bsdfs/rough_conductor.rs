//! Mitsuba's `roughconductor` (WGSL: `shaders/bsdfs/rough_conductor.wgsl`): Torrance-Sparrow
//! microfacet reflection with the conductor's Fresnel term and separable Smith shadowing. TOML
//! the conductor's `eta`, `k`, `specular_reflectance`, and `distribution` (`beckmann`, Mitsuba's
//! default, or `ggx`) and `alpha` (default 0.1; below 1e-4 clamped to it, as Mitsuba does).

use super::conductor::Conductor;
use super::distribution::Distribution;
use super::plugin::{BsdfParams, BsdfPlugin, Fields, PluginProps};
use crate::names::Named;

/// Mitsuba's floor on a rough conductor's alpha (smaller values are clamped to it).
const MIN_ALPHA: f64 = 1e-4;
/// Mitsuba's default alpha.
const DEFAULT_ALPHA: f64 = 0.1;

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
    const FIELDS: &'static [&'static str] = &["distribution", "alpha", "eta", "k", "specular_reflectance"];
    const MITSUBA_PLUGINS: &'static [&'static str] = &["roughconductor"];
    const IS_DELTA: bool = false;

    fn from_fields(f: &mut Fields) -> RoughConductor {
        let fresnel = Conductor::read_fresnel(f);
        let distribution = match f.string("distribution") {
            None => Distribution::Beckmann,
            Some(d) => Distribution::from_name(d.get_ref()).unwrap_or_else(|| {
                f.error(d.span(), "distribution", format!("unknown distribution \"{}\" (known: \"beckmann\", \"ggx\")", d.get_ref()));
                Distribution::Beckmann
            }),
        };
        let alpha = match f.number("alpha") {
            None => DEFAULT_ALPHA,
            Some(a) => {
                let v = *a.get_ref();
                if !(v > 0.0) {
                    f.error(a.span(), "alpha", format!("alpha must be > 0 (got {v}); a smooth conductor is bsdf = \"conductor\""));
                } else if v < MIN_ALPHA {
                    f.warn(a.span(), "alpha", format!("alpha {v} is below {MIN_ALPHA}: it is clamped to {MIN_ALPHA}, as Mitsuba does"));
                }
                v.max(MIN_ALPHA)
            }
        };
        RoughConductor { fresnel, distribution, alpha }
    }

    fn from_mitsuba(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
        let mut fields = Conductor::mitsuba_fresnel(p);
        let distribution = match p.string("distribution") {
            None => "beckmann".to_string(),
            Some((d, at)) => {
                let d = d.to_ascii_lowercase();
                if Distribution::from_name(&d).is_none() {
                    p.error(at, "distribution", format!("unknown distribution \"{d}\" (beckmann, ggx)"));
                }
                d
            }
        };
        for name in ["alpha_u", "alpha_v"] {
            if let Some(at) = p.take(name) {
                p.error(at, name, format!("`{name}`: anisotropic roughness is not supported (give one `alpha`)"));
            }
        }
        let alpha = match p.float("alpha") {
            None => Some(DEFAULT_ALPHA),
            Some((a, _)) if a.is_finite() && a > 0.0 => Some(a),
            Some((a, at)) => {
                p.error(at, "alpha", format!("`alpha` of <bsdf type=\"roughconductor\"> must be a finite number > 0 (got {a})"));
                None
            }
        };
        if let Some(at) = p.take("sample_visible") {
            p.warn(
                at,
                "sample_visible",
                "`sample_visible` is ignored: pathlab's microfacet sampling is --microfacet-sampling (vndf by default); the expected image is the same".into(),
            );
        }
        p.finish("distribution, alpha, eta, k, specular_reflectance, material=\"none\" (and, with a warning, sample_visible)");
        fields.push(("distribution", toml::Value::String(distribution)));
        fields.push(("alpha", toml::Value::Float(alpha?)));
        Some(fields)
    }

    fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        self.fresnel.fresnel_hash_lines(line);
        line("conductor.rough", format!("{} {}", self.distribution, crate::scene::hash::real(self.alpha)));
    }

    fn pack(&self) -> BsdfParams {
        self.fresnel.pack_with(self.alpha, self.distribution)
    }
}
