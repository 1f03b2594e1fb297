//! Mitsuba's `roughplastic` (WGSL: `shaders/bsdfs/rough_plastic.wgsl`): a diffuse base under a
//! rough dielectric coating, term for term as Mitsuba 3's `roughplastic.cpp`. The coating
//! reflects by Torrance-Sparrow microfacets with the dielectric's Fresnel term (times
//! `specular_reflectance`):
//!
//!   f_spec(wi, wo) = F(wi . h) D(h) G(wi, wo, h) / (4 cos_i cos_o);
//!
//! the light it transmits scatters diffusely inside and leaves:
//!
//!   f_diff(wi, wo) = R / (1 - R_int) T(cos_i) T(cos_o) / (pi eta^2),
//!
//! with R = `diffuse_reflectance` (R R_int for R_int with `nonlinear`), T(cos) the rough
//! coating's transmittance at incidence cos (the mean over the normals visible from the
//! direction of G1(out, m)(1 - F(wi . m)), Mitsuba's `eval_transmittance`) and R_int the
//! internal reflectance seen from inside (2 mean over 64 cosines mu of mu times the coating's
//! reflectance at index 1 / eta, `eval_reflectance`). Both are computed here once per material
//! and read by the kernel from the BSDF data (`BsdfData`): T at Mitsuba's 64 cosines
//! max(1e-6, k / 63), interpolated linearly between them as its `lerp_gather` does, then
//! R_int. Its own sampling picks the coating's lobe with probability (1 - T(cos_i)) w / ((1 -
//! T(cos_i)) w + T(cos_i)(1 - w)), w = `specular_sampling_weight` from the albedos (the
//! `--lobe-selection fixed` strategy: w alone), drawing a microfacet normal by
//! `--microfacet-sampling`, else a cosine-weighted direction. One sided.
//!
//! TOML and Mitsuba: plastic's `diffuse_reflectance`, `specular_reflectance`, `int_ior`,
//! `ext_ior`, `nonlinear`, and the rough kinds' `distribution` and `alpha`.

use glam::DVec3;

use super::distribution::{self, Distribution};
use super::fresnel::fresnel_dielectric;
use super::plastic::Plastic;
use super::plugin::{BsdfData, BsdfParams, BsdfPlugin, Fields, PluginProps};
use crate::scene::hash::real;

/// Entries of the transmittance table (Mitsuba's `MI_ROUGH_TRANSMITTANCE_RES`); generated into
/// the WGSL as `ROUGH_PLASTIC_TABLE_RES`.
pub const TRANSMITTANCE_RES: usize = 64;
/// Gauss-Legendre nodes per dimension of the visible-normal quadrature
/// (`Distribution::visible_normal_mean`) of the transmittance and of the internal reflectance:
/// with four times as many, T moves by less than 1e-5 and R_int by less than 5e-4 (its
/// Fresnel term's square-root kink at the critical angle converges slowest; the image moves by
/// less than 5e-4 / (1 - R_int), relative). Mitsuba's own quadrature uses 32^2 and 128^2 nodes.
const QUADRATURE_NODES: (usize, usize) = (64, 128);

#[derive(Debug, Clone, PartialEq)]
pub struct RoughPlastic {
    /// The base, the coating's indices and `nonlinear`, as a smooth plastic's.
    pub layers: Plastic,
    pub distribution: Distribution,
    /// The roughness, >= 1e-4.
    pub alpha: f64,
}

/// The coating's precomputed terms: T at Mitsuba's 64 cosines, and the internal reflectance.
#[derive(Debug, Clone, PartialEq)]
pub struct CoatingTables {
    pub transmittance: Vec<f64>,
    pub internal_reflectance: f64,
}

impl RoughPlastic {
    /// The cosines of the table's entries: max(1e-6, k / 63), as Mitsuba's.
    pub fn table_cosines() -> Vec<f64> {
        (0..TRANSMITTANCE_RES).map(|k| (k as f64 / (TRANSMITTANCE_RES - 1) as f64).max(1e-6)).collect()
    }

    /// The coating's transmittance and internal reflectance (Mitsuba's `parameters_changed`).
    pub fn coating_tables(&self) -> CoatingTables {
        self.coating_tables_with(QUADRATURE_NODES)
    }

    fn coating_tables_with(&self, (t_nodes, r_nodes): (usize, usize)) -> CoatingTables {
        let (d, alpha, eta) = (self.distribution, self.alpha, self.layers.eta());
        let cosines = Self::table_cosines();
        let incident = |mu: f64| DVec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
        // T(mu): G1 of the refracted direction times the Fresnel transmittance, 0 where the
        // refraction stays on the side of incidence (total internal reflection).
        let transmittance = cosines
            .iter()
            .map(|&mu| {
                let wi = incident(mu);
                d.visible_normal_mean(wi, alpha, t_nodes, |m| {
                    let cos_im = wi.dot(m);
                    let (f, cos_t) = fresnel_dielectric(cos_im, eta);
                    let eta_ti = 1.0 / eta;
                    let wo = m * (cos_im * eta_ti + cos_t) - wi * eta_ti;
                    if wo.z * wi.z >= 0.0 {
                        0.0
                    } else {
                        d.smith_g1(wo, m, alpha) * (1.0 - f)
                    }
                })
            })
            .collect();
        // The reflectance at index 1 / eta (from inside), times mu, averaged over the same
        // cosines, times 2: Mitsuba's Riemann mean of the cosine-weighted hemisphere.
        let reflectance_sum: f64 = cosines
            .iter()
            .map(|&mu| {
                let wi = incident(mu);
                let r = d.visible_normal_mean(wi, alpha, r_nodes, |m| {
                    let cos_im = wi.dot(m);
                    let wo = 2.0 * cos_im * m - wi;
                    if wo.z <= 0.0 {
                        0.0
                    } else {
                        d.smith_g1(wo, m, alpha) * fresnel_dielectric(cos_im, 1.0 / eta).0
                    }
                });
                r * mu
            })
            .sum();
        CoatingTables { transmittance, internal_reflectance: 2.0 * reflectance_sum / TRANSMITTANCE_RES as f64 }
    }
}

impl BsdfPlugin for RoughPlastic {
    const TOML_NAME: &'static str = "roughplastic";
    const FIELDS: &'static [&'static str] =
        &["diffuse_reflectance", "specular_reflectance", "int_ior", "ext_ior", "nonlinear", "distribution", "alpha"];
    const MITSUBA_PLUGINS: &'static [&'static str] = &["roughplastic"];
    const IS_DELTA: bool = false;
    const SELECTS_LOBES: bool = true;
    const MICROFACETS: bool = true;
    const TEXTURE_SLOTS: &'static [usize] = &[0];

    fn from_fields(f: &mut Fields) -> RoughPlastic {
        let layers = Plastic::from_fields(f);
        let (distribution, roughness) = distribution::read_fields(f, "plastic", false, false);
        let alpha = roughness.alpha;
        RoughPlastic { layers, distribution, alpha }
    }

    fn from_mitsuba(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
        let mut fields = Plastic::mitsuba_layers(p);
        let microfacets = distribution::read_mitsuba(p, false, false);
        p.finish("diffuse_reflectance, specular_reflectance, int_ior, ext_ior, nonlinear, distribution, alpha (and, with a warning, sample_visible)");
        fields.extend(microfacets?);
        Some(fields)
    }

    fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
        self.layers.hash_lines(line);
        line("plastic.rough", format!("{} {}", self.distribution, real(self.alpha)));
    }

    /// `p0 = (diffuse, eta)`, `p1 = (specular, specular_sampling_weight)`, `p2 = (alpha,
    /// distribution, nonlinear, first BSDF datum)`: the layout of WGSL's `rough_plastic_of`;
    /// the data: T at the 64 cosines, then R_int.
    fn textures(&self) -> Vec<&crate::scene::Texture> {
        self.layers.diffuse_texture.iter().collect()
    }

    fn pack(&self, data: &mut BsdfData) -> BsdfParams {
        let p = &self.layers;
        let (d, s) = (p.diffuse_slot(data), p.specular.as_vec3());
        let tables = self.coating_tables();
        let mut values: Vec<f32> = tables.transmittance.iter().map(|&t| t as f32).collect();
        values.push(tables.internal_reflectance as f32);
        let first = data.push(&values);
        [
            [d.x, d.y, d.z, p.eta() as f32],
            [s.x, s.y, s.z, p.specular_sampling_weight() as f32],
            [self.alpha as f32, self.distribution.constant() as f32, if p.nonlinear { 1.0 } else { 0.0 }, first as f32],
            [0.0; 4],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn coating(distribution: Distribution, alpha: f64, int_ior: f64) -> RoughPlastic {
        let layers = Plastic { diffuse: DVec3::splat(0.5), diffuse_texture: None, specular: DVec3::ONE, int_ior, ext_ior: 1.0, nonlinear: false };
        RoughPlastic { layers, distribution, alpha }
    }

    /// The visible normals' quadrature integrates their density to 1, from normal to grazing
    /// incidence (the exact G1 normalises it), for both distributions from alpha 1e-4 to 1.
    #[test]
    fn visible_normals_have_mass_one() {
        for d in [Distribution::Beckmann, Distribution::Ggx] {
            for alpha in [1e-4, 0.01, 0.1, 0.5, 1.0] {
                for mu in [1e-6f64, 0.01, 0.2, 0.7, 1.0] {
                    let wi = DVec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
                    let mass = d.visible_normal_mean(wi, alpha, QUADRATURE_NODES.0, |_| 1.0);
                    assert!((mass - 1.0).abs() < 2e-6, "{d:?} alpha {alpha} mu {mu}: mass {mass}");
                }
            }
        }
    }

    /// Index-matched (F = 0, the refraction straight through), the transmittance is the mean of
    /// G1(-wi, m) over the visible normals, which for Smith's separable G1 is G1(wi) itself:
    /// Mitsuba's fit for Beckmann, GGX's closed form.
    #[test]
    fn an_index_matched_coating_transmits_g1() {
        for d in [Distribution::Beckmann, Distribution::Ggx] {
            for alpha in [0.05, 0.3, 1.0] {
                let tables = coating(d, alpha, 1.0).coating_tables();
                for (mu, t) in RoughPlastic::table_cosines().into_iter().zip(&tables.transmittance) {
                    let wi = DVec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
                    let g1 = d.smith_g1(wi, DVec3::Z, alpha);
                    assert!((t - g1).abs() < 2e-5, "{d:?} alpha {alpha} mu {mu}: T {t}, G1 {g1}");
                }
                assert_eq!(tables.internal_reflectance, 0.0);
            }
        }
    }

    /// A nearly smooth coating transmits 1 - F(cos) (at any cosine the quadrature resolves),
    /// and its internal reflectance is Mitsuba's Riemann mean of the smooth reflectance.
    #[test]
    fn a_nearly_smooth_coating_is_the_smooth_interface() {
        let tables = coating(Distribution::Ggx, 1e-4, 1.5).coating_tables();
        let cosines = RoughPlastic::table_cosines();
        for (mu, t) in cosines.iter().zip(&tables.transmittance).skip(1) {
            let smooth = 1.0 - fresnel_dielectric(*mu, 1.5).0;
            assert!((t - smooth).abs() < 1e-3, "mu {mu}: T {t}, smooth {smooth}");
        }
        let riemann: f64 = cosines.iter().map(|&mu| fresnel_dielectric(mu, 1.0 / 1.5).0 * mu).sum::<f64>() * 2.0 / 64.0;
        assert!((tables.internal_reflectance - riemann).abs() < 2e-3, "R_int {} against {riemann}", tables.internal_reflectance);
    }

    /// The quadrature has converged: four times the nodes move no transmittance by more than 1e-5
    /// and the internal reflectance by no more than 5e-4.
    #[test]
    fn the_tables_have_converged() {
        for d in [Distribution::Beckmann, Distribution::Ggx] {
            for alpha in [1e-3, 0.1, 0.5, 1.0] {
                let p = coating(d, alpha, 1.49);
                let (t, r) = QUADRATURE_NODES;
                let (a, b) = (p.coating_tables_with((t, r)), p.coating_tables_with((4 * t, 4 * r)));
                for (x, y) in a.transmittance.iter().zip(&b.transmittance) {
                    assert!((x - y).abs() < 1e-5, "{d:?} alpha {alpha}: {x} against {y}");
                }
                let (ra, rb) = (a.internal_reflectance, b.internal_reflectance);
                assert!((ra - rb).abs() < 5e-4, "{d:?} alpha {alpha}: R_int {ra} against {rb}");
            }
        }
    }
}
