//! What the microfacet BSDFs share: the distribution of normals and its roughness (its WGSL in
//! the microfacet shader file), read the same way for every rough kind.

use super::plugin::{Fields, PluginProps};
use crate::names::Named;

/// Mitsuba's floor on a microfacet roughness (`MicrofacetDistribution` clamps to it).
pub(crate) const MIN_ALPHA: f64 = 1e-4;
/// Mitsuba's default alpha.
pub(crate) const DEFAULT_ALPHA: f64 = 0.1;

crate::names::named_enum! {
    /// The microfacet distribution of a rough BSDF (`shaders/microfacet.wgsl`).
    pub enum Distribution("microfacet distribution") {
        /// Beckmann's (Mitsuba's default).
        Beckmann = "beckmann",
        /// Trowbridge-Reitz / GGX: longer tails.
        Ggx = "ggx",
    }
}

/// A rough kind's `distribution` and `alpha` from its TOML fields: Beckmann and 0.1 by default,
/// alpha > 0 required (`smooth` names the smooth kind to use instead), and below 1e-4 clamped
/// to it with a warning, as Mitsuba does.
pub(crate) fn read_fields(f: &mut Fields, smooth: &str) -> (Distribution, f64) {
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
                f.error(a.span(), "alpha", format!("alpha must be > 0 (got {v}); a smooth one is bsdf = \"{smooth}\""));
            } else if v < MIN_ALPHA {
                f.warn(a.span(), "alpha", format!("alpha {v} is below {MIN_ALPHA}: it is clamped to {MIN_ALPHA}, as Mitsuba does"));
            }
            v.max(MIN_ALPHA)
        }
    };
    (distribution, alpha)
}

/// A rough Mitsuba plugin's `distribution` and `alpha` as TOML fields (anisotropic roughness
/// refused, `sample_visible` taken with a warning: the strategy is `--microfacet-sampling`);
/// `None` when an error was reported.
pub(crate) fn read_mitsuba(p: &mut dyn PluginProps) -> Option<[(&'static str, toml::Value); 2]> {
    let plugin = p.plugin().to_string();
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
            p.error(at, "alpha", format!("`alpha` of <bsdf type=\"{plugin}\"> must be a finite number > 0 (got {a})"));
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
    Some([("distribution", toml::Value::String(distribution)), ("alpha", toml::Value::Float(alpha?))])
}
