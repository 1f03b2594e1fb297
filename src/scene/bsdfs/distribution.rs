//! What the microfacet BSDFs share: the distribution of normals and its roughness (its WGSL in
//! the microfacet shader file), read the same way for every rough kind.

use glam::DVec3;

use super::plugin::{BsdfData, Fields, PluginProps};
use crate::scene::hash::real;
use crate::scene::textures::Texture;
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

/// A rough kind's roughness: `alpha`, or a texture of it (Mitsuba's `eval_1` of it at the hit,
/// `Texture::scalar`; `alpha` is then its mean, for what the host computes); or, anisotropic,
/// Mitsuba's `alpha_u` (in `alpha`, `texture`) along the surface's dp/du and `alpha_v` (in
/// `alpha_v`, `texture_v`) across it, each a number or a texture.
#[derive(Debug, Clone, PartialEq)]
pub struct Roughness {
    /// >= 1e-4; alpha_u where `alpha_v` is given.
    pub alpha: f64,
    pub texture: Option<Texture>,
    /// Mitsuba's `alpha_v` (>= 1e-4; a textured one's mean) where the roughness is given as
    /// `alpha_u` and `alpha_v`; `None`: the same along both.
    pub alpha_v: Option<f64>,
    /// A textured `alpha_v` (`Texture::scalar`).
    pub texture_v: Option<Texture>,
}

impl Roughness {
    /// One alpha along both directions.
    pub fn isotropic(alpha: f64) -> Roughness {
        Roughness { alpha, texture: None, alpha_v: None, texture_v: None }
    }

    /// Whether it differs along u and v (the kernel's `ANISOTROPIC_ROUGHNESS`, and tangent
    /// frames at hits).
    pub fn is_anisotropic(&self) -> bool {
        self.alpha_v.is_some_and(|v| v != self.alpha || self.texture.is_some() || self.texture_v.is_some())
    }

    /// Its textures: alpha's (or alpha_u's), then alpha_v's.
    pub fn textures(&self) -> impl Iterator<Item = &Texture> {
        self.texture.iter().chain(self.texture_v.iter())
    }

    /// Its alpha_v in the parameter block (a scalar texture slot): -0.0 where it is isotropic
    /// (the kernel then takes alpha_u; the sign bit tells it from a textured alpha_v that is 0
    /// somewhere, which Mitsuba clamps to 1e-4), -(start + 1) of a texture's record, or alpha_v.
    pub fn pack_v(&self, data: &mut BsdfData) -> f32 {
        match (&self.texture_v, self.alpha_v) {
            (Some(t), _) => -(t.pack(data) as f32) - 1.0,
            (None, Some(v)) => v as f32,
            (None, None) => -0.0,
        }
    }

    /// Its number in the parameter block: alpha, or -(start + 1) of its texture's record (a
    /// scalar texture slot, resolved in the kernel and clamped there to 1e-4 as Mitsuba's
    /// `MicrofacetDistribution::configure`).
    pub fn pack(&self, data: &mut BsdfData) -> f32 {
        match &self.texture {
            Some(t) => -(t.pack(data) as f32) - 1.0,
            None => self.alpha as f32,
        }
    }

    /// Its value in the scene hash: alpha, and a texture's line after it, or alpha_u and
    /// alpha_v (an isotropic roughness hashes as before alpha_v existed).
    pub fn hash_value(&self) -> String {
        let texture = |t: &Texture| t.hash_value(crate::scene::hash::vec3);
        match (&self.texture, self.alpha_v, &self.texture_v) {
            (None, Some(v), None) => format!("{} v {}", real(self.alpha), real(v)),
            (u, Some(v), tv) => format!(
                "{}{} v {}{}",
                real(self.alpha),
                u.as_ref().map_or(String::new(), |t| format!(" {}", texture(t))),
                real(v),
                tv.as_ref().map_or(String::new(), |t| format!(" {}", texture(t)))
            ),
            (None, None, _) => real(self.alpha),
            (Some(t), None, _) => format!("{} {}", real(self.alpha), texture(t)),
        }
    }
}

/// One roughness number of a TOML field: > 0 required (`smooth` names the smooth kind to use
/// instead), and below 1e-4 clamped to it with a warning, as Mitsuba does.
fn read_alpha(f: &mut Fields, name: &str, smooth: &str) -> Option<f64> {
    let a = f.number(name)?;
    let v = *a.get_ref();
    if !(v > 0.0) {
        f.error(a.span(), name, format!("{name} must be > 0 (got {v}); a smooth one is bsdf = \"{smooth}\""));
    } else if v < MIN_ALPHA {
        f.warn(a.span(), name, format!("{name} {v} is below {MIN_ALPHA}: it is clamped to {MIN_ALPHA}, as Mitsuba does"));
    }
    Some(v.max(MIN_ALPHA))
}

/// A rough kind's `distribution` and `alpha` from its TOML fields: Beckmann and 0.1 by default,
/// alpha > 0 required (`smooth` names the smooth kind to use instead), and below 1e-4 clamped
/// to it with a warning, as Mitsuba does. Where `textured`, alpha may be a texture table. Where
/// `anisotropic`, `alpha_u` and `alpha_v` (numbers, both, and not with `alpha`, as Mitsuba
/// requires) may take its place.
pub(crate) fn read_fields(f: &mut Fields, smooth: &str, textured: bool, anisotropic: bool) -> (Distribution, Roughness) {
    let distribution = match f.string("distribution") {
        None => Distribution::Beckmann,
        Some(d) => Distribution::from_name(d.get_ref()).unwrap_or_else(|| {
            f.error(d.span(), "distribution", format!("unknown distribution \"{}\" (known: \"beckmann\", \"ggx\")", d.get_ref()));
            Distribution::Beckmann
        }),
    };
    if anisotropic && (f.has("alpha_u") || f.has("alpha_v")) {
        let span = f.span_of(if f.has("alpha_u") { "alpha_u" } else { "alpha_v" });
        if f.has("alpha") {
            f.error(span.clone(), "alpha_u", "give either `alpha` or `alpha_u` and `alpha_v`, not both (as Mitsuba requires)".to_string());
        }
        // Each a number or, where `textured`, a texture (Mitsuba's eval_1 of it; its mean for
        // what the host computes).
        let one = |f: &mut Fields, name: &str| -> Option<(f64, Option<Texture>)> {
            if f.is_table(name) {
                if !textured {
                    let at = f.span_of(name);
                    f.error(at, name, format!("{name} of this kind must be a number"));
                    return Some((DEFAULT_ALPHA, None));
                }
                let (_, texture) = f.color_or_texture(name, glam::DVec3::splat(DEFAULT_ALPHA));
                let texture = texture.map(Texture::scalar);
                let mean = texture.as_ref().map_or(DEFAULT_ALPHA, |t| crate::scene::emitters::luminance(t.mean())).max(MIN_ALPHA);
                return Some((mean, texture));
            }
            read_alpha(f, name, smooth).map(|a| (a, None))
        };
        let (u, v) = (one(f, "alpha_u"), one(f, "alpha_v"));
        return match (u, v) {
            (Some((u, texture)), Some((v, texture_v))) => (distribution, Roughness { alpha: u, texture, alpha_v: Some(v), texture_v }),
            _ => {
                f.error(span, "alpha_u", "give both `alpha_u` and `alpha_v` (as Mitsuba requires)".to_string());
                (distribution, Roughness::isotropic(DEFAULT_ALPHA))
            }
        };
    }
    if f.is_table("alpha") {
        if !textured {
            let span = f.span_of("alpha");
            f.error(span, "alpha", "alpha of this kind must be a number: Mitsuba's roughplastic precomputes its coating for one roughness".to_string());
            return (distribution, Roughness::isotropic(DEFAULT_ALPHA));
        }
        let (_, texture) = f.color_or_texture("alpha", glam::DVec3::splat(DEFAULT_ALPHA));
        let texture = texture.map(Texture::scalar);
        let alpha = texture.as_ref().map_or(DEFAULT_ALPHA, |t| crate::scene::emitters::luminance(t.mean())).max(MIN_ALPHA);
        return (distribution, Roughness { alpha, texture, alpha_v: None, texture_v: None });
    }
    (distribution, Roughness::isotropic(read_alpha(f, "alpha", smooth).unwrap_or(DEFAULT_ALPHA)))
}

/// A rough Mitsuba plugin's `distribution` and `alpha` (or, where `anisotropic`, `alpha_u` and
/// `alpha_v`: both, numbers, not with `alpha`) as TOML fields (`sample_visible` taken with a
/// warning: the strategy is `--microfacet-sampling`); `None` when an error was reported.
pub(crate) fn read_mitsuba(p: &mut dyn PluginProps, textured: bool, anisotropic: bool) -> Option<Vec<(&'static str, toml::Value)>> {
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
    let sample_visible = |p: &mut dyn PluginProps| {
        if let Some(at) = p.take("sample_visible") {
            p.warn(
                at,
                "sample_visible",
                "`sample_visible` is ignored: pathlab's microfacet sampling is --microfacet-sampling (vndf by default); the expected image is the same".into(),
            );
        }
    };
    if !anisotropic {
        for name in ["alpha_u", "alpha_v"] {
            if let Some(at) = p.take(name) {
                p.error(at, name, format!("`{name}`: <bsdf type=\"{plugin}\"> has one `alpha` (Mitsuba's is isotropic)"));
            }
        }
    } else if p.has("alpha_u") || p.has("alpha_v") {
        // Mitsuba's microfacet constructor: both, and not with `alpha`.
        let mut values = Vec::new();
        for name in ["alpha_u", "alpha_v"] {
            if p.has_texture(name) {
                if textured {
                    if let Some(t) = p.color_or_texture(name) {
                        values.push((name, t));
                    }
                } else {
                    p.error(p.at(), name, format!("a textured `{name}` of <bsdf type=\"{plugin}\"> is not supported (give a <float>)"));
                    let _ = p.color_or_texture(name);
                }
                continue;
            }
            match p.float(name) {
                None => p.error(p.at(), name, format!("give both `alpha_u` and `alpha_v` (Mitsuba: \"Microfacet model: both 'alpha_u' and 'alpha_v' must be specified.\")")),
                Some((a, _)) if a.is_finite() && a > 0.0 => values.push((name, toml::Value::Float(a))),
                Some((a, at)) => p.error(at, name, format!("`{name}` of <bsdf type=\"{plugin}\"> must be a finite number > 0 (got {a})")),
            }
        }
        if let Some(at) = p.take("alpha") {
            p.error(at, "alpha", "give either `alpha` or `alpha_u` and `alpha_v`, not both (as Mitsuba requires)".into());
            return None;
        }
        sample_visible(p);
        if values.len() != 2 {
            return None;
        }
        let mut fields = vec![("distribution", toml::Value::String(distribution))];
        fields.extend(values);
        return Some(fields);
    }
    let alpha = if p.has_texture("alpha") {
        if textured {
            p.color_or_texture("alpha")
        } else {
            p.error(p.at(), "alpha", format!("a textured `alpha` of <bsdf type=\"{plugin}\"> is not supported (Mitsuba's roughplastic takes a number)"));
            None
        }
    } else {
        match p.float("alpha") {
            None => Some(toml::Value::Float(DEFAULT_ALPHA)),
            Some((a, _)) if a.is_finite() && a > 0.0 => Some(toml::Value::Float(a)),
            Some((a, at)) => {
                p.error(at, "alpha", format!("`alpha` of <bsdf type=\"{plugin}\"> must be a finite number > 0 (got {a})"));
                None
            }
        }
    };
    sample_visible(p);
    Some(vec![("distribution", toml::Value::String(distribution)), ("alpha", alpha?)])
}

// ----- the host's microfacet maths, for precomputed tables (the kernel's: shaders/microfacet.wgsl)

impl Distribution {
    /// Smith's G1(v, m) as Mitsuba's `smith_g1` evaluates it (Beckmann: Walter's rational fit
    /// of 1 / (1 + Lambda)), in a frame whose +z is the macro-normal: 0 where v sees the back
    /// of m.
    pub(crate) fn smith_g1(self, v: DVec3, m: DVec3, alpha: f64) -> f64 {
        if v.dot(m) * v.z <= 0.0 {
            return 0.0;
        }
        let xy_alpha_2 = alpha * alpha * (v.x * v.x + v.y * v.y);
        if xy_alpha_2 == 0.0 {
            return 1.0;
        }
        let tan_theta_alpha_2 = xy_alpha_2 / (v.z * v.z);
        match self {
            Distribution::Beckmann => {
                let a = 1.0 / tan_theta_alpha_2.sqrt();
                if a >= 1.6 {
                    1.0
                } else {
                    (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
                }
            }
            Distribution::Ggx => 2.0 / (1.0 + (1.0 + tan_theta_alpha_2).sqrt()),
        }
    }

    /// The exact Smith G1 = 1 / (1 + Lambda(v)): the normalisation of the normals visible from
    /// v, which Mitsuba's visible-normal sampler draws exactly (Beckmann: Lambda(a) = (erf(a) -
    /// 1) / 2 + exp(-a^2) / (2 a sqrt(pi)), a = 1 / (alpha tan(theta_v)); GGX's is its fit).
    fn smith_g1_exact(self, v: DVec3, m: DVec3, alpha: f64) -> f64 {
        match self {
            Distribution::Ggx => self.smith_g1(v, m, alpha),
            Distribution::Beckmann => {
                if v.dot(m) * v.z <= 0.0 {
                    return 0.0;
                }
                let xy = (v.x * v.x + v.y * v.y).sqrt();
                if xy == 0.0 {
                    return 1.0;
                }
                let a = v.z / (alpha * xy);
                let lambda = 0.5 * (statrs::function::erf::erf(a) - 1.0) + (-a * a).exp() / (2.0 * a * std::f64::consts::PI.sqrt());
                1.0 / (1.0 + lambda)
            }
        }
    }

    /// The mean of g(m) over the normals visible from wi (density D(m) G1(wi, m) max(0, wi . m)
    /// / cos(theta_i), wi in the xz-plane with wi.z > 0): the quantity Mitsuba's
    /// `eval_reflectance` and `eval_transmittance` (microfacet.h) estimate with 32^2 or 128^2
    /// Gauss-Legendre nodes over its visible-normal sampler. Here in the space of slopes scaled
    /// by alpha, (p, q) = -(m.x, m.y) / (alpha m.z), where D(m) cos(theta_m) dm is the slope
    /// density P(p, q) dp dq (Beckmann: exp(-p^2 - q^2) / pi; GGX: 1 / (pi (1 + p^2 + q^2)^2))
    /// and the visible normals' factor is (cos_i - alpha p sin_i) / cos_i G1(wi), zero beyond
    /// p = a = cot(theta_i) / alpha. Beckmann's slopes are integrated over [-6, min(a, 6)] x [-6,
    /// 6] (the Gaussian is below 3e-16 beyond); GGX's heavy tails through p = tan(psi), q =
    /// sqrt(1 + p^2) tan(chi), which make the integrand smooth on bounded intervals. `n`
    /// Gauss-Legendre nodes per dimension.
    pub(crate) fn visible_normal_mean(self, wi: DVec3, alpha: f64, n: usize, g: impl Fn(DVec3) -> f64) -> f64 {
        use std::f64::consts::{FRAC_PI_2, PI};
        let nodes = gauss_legendre(n);
        let (cos_i, sin_i) = (wi.z, wi.x);
        let a = if sin_i > 0.0 { cos_i / (alpha * sin_i) } else { f64::INFINITY };
        // G1(wi) for every visible normal (the exact Smith normalisation).
        let g1 = self.smith_g1_exact(wi, DVec3::Z, alpha);
        let value = |p: f64, q: f64| {
            let m = DVec3::new(-alpha * p, -alpha * q, 1.0).normalize();
            g1 * (cos_i - alpha * p * sin_i) / cos_i * g(m)
        };
        // Gauss-Legendre over [lo, hi] of f.
        let integrate = |lo: f64, hi: f64, f: &dyn Fn(f64) -> f64| -> f64 {
            nodes.iter().map(|&(x, w)| w * f(lo + (hi - lo) * 0.5 * (x + 1.0))).sum::<f64>() * 0.5 * (hi - lo)
        };
        match self {
            Distribution::Beckmann => integrate(-6.0, a.min(6.0), &|p| {
                integrate(-6.0, 6.0, &|q| (-p * p - q * q).exp() / PI * value(p, q))
            }),
            Distribution::Ggx => integrate(-FRAC_PI_2, a.atan(), &|psi| {
                let p = psi.tan();
                let c = (1.0 + p * p).sqrt();
                // dp = sec^2(psi) dpsi; dq = c sec^2(chi) dchi; 1 + p^2 + q^2 = c^2 sec^2(chi).
                integrate(-FRAC_PI_2, FRAC_PI_2, &|chi| {
                    let q = c * chi.tan();
                    let density = chi.cos().powi(2) / (PI * c.powi(3));
                    density * value(p, q) / psi.cos().powi(2)
                })
            }),
        }
    }
}

/// The n-point Gauss-Legendre rule on [-1, 1]: (node, weight), the nodes found by Newton's
/// iteration on the Legendre polynomial P_n from Chebyshev's estimates.
pub(crate) fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    use std::f64::consts::PI;
    (0..n)
        .map(|i| {
            let mut x = -(PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                // P_n(x) and P_n'(x) by the three-term recurrence.
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let k = k as f64;
                    let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                let p = if n == 0 { 1.0 } else { p1 };
                dp = n as f64 * (x * p - p0) / (x * x - 1.0);
                let dx = p / dp;
                x -= dx;
                if dx.abs() < 1e-15 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}
