//! The scene's lights in kernel order, their emitted power, and the alias table power
//! selection draws from.
//!
//! Light l is an emissive sphere (all of them first, in scene order: the kernel's sphere l) or
//! an emissive triangle (then, mesh by mesh, triangle by triangle). This order fixes which
//! sample dimensions each light uses when every light is sampled.

use glam::DVec3;

use super::Scene;
use crate::method::LightSelect;

/// One light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// Index into `Scene::spheres`.
    Sphere(usize),
    /// Triangle `triangle` of `Scene::meshes[mesh]`.
    Triangle { mesh: usize, triangle: usize },
}

/// Rec. 709 luminance, the weight of a colour in power selection.
pub fn luminance(c: DVec3) -> f64 {
    c.dot(DVec3::new(0.212671, 0.715160, 0.072169))
}

impl Scene {
    /// Every light, in kernel order.
    pub fn lights(&self) -> Vec<Light> {
        let spheres = self.light_spheres().into_iter().map(Light::Sphere);
        let triangles = self.meshes.iter().enumerate().filter(|(_, m)| self.materials[m.material].is_emissive()).flat_map(
            |(mesh, m)| (0..m.triangles.len()).map(move |triangle| Light::Triangle { mesh, triangle }),
        );
        spheres.chain(triangles).collect()
    }

    /// How many lights `lights()` lists (the emissive spheres, then every emissive triangle),
    /// counted without listing them.
    pub fn num_lights(&self) -> usize {
        let triangles: usize = self.meshes.iter().filter(|m| self.materials[m.material].is_emissive()).map(|m| m.triangles.len()).sum();
        self.light_spheres().len() + triangles
    }

    /// Whether any mesh emits.
    pub fn has_triangle_lights(&self) -> bool {
        self.meshes.iter().any(|m| self.materials[m.material].is_emissive())
    }

    /// The light selection of a method that leaves it open (the one place it is decided):
    /// `power` for scenes with emissive meshes (a mesh of a thousand triangles is a thousand
    /// lights), else `all`, which keeps the images of sphere-lit scenes as they were.
    pub fn default_light_select(&self) -> LightSelect {
        if self.has_triangle_lights() { LightSelect::Power } else { LightSelect::All }
    }

    /// Emitted power of a light, in luminance: pi times area times radiance for a diffuse
    /// emitter, twice that for a two-sided one (spheres emit outwards only).
    pub fn light_power(&self, light: Light) -> f64 {
        use std::f64::consts::PI;
        match light {
            Light::Sphere(i) => {
                let s = &self.spheres[i];
                PI * 4.0 * PI * s.radius * s.radius * luminance(self.materials[s.material].emission)
            }
            Light::Triangle { mesh, triangle } => {
                let m = &self.meshes[mesh];
                let sides = if m.two_sided_emission { 2.0 } else { 1.0 };
                PI * sides * m.triangle_area(triangle) * luminance(self.materials[m.material].emission)
            }
        }
    }
}

/// Walker's alias table (Vose's construction): slot i keeps item i with probability
/// `threshold[i]`, else gives `alias[i]`; a slot drawn uniformly then yields item j with
/// probability `prob[j]`, the normalised weight.
#[derive(Debug, Clone, PartialEq)]
pub struct AliasTable {
    pub prob: Vec<f64>,
    pub threshold: Vec<f64>,
    pub alias: Vec<u32>,
}

impl AliasTable {
    /// The table of non-negative `weights` (uniform if they sum to zero).
    pub fn new(weights: &[f64]) -> AliasTable {
        let n = weights.len();
        let total: f64 = weights.iter().sum();
        let prob: Vec<f64> = if total > 0.0 { weights.iter().map(|w| w / total).collect() } else { vec![1.0 / n as f64; n] };
        let mut scaled: Vec<f64> = prob.iter().map(|p| p * n as f64).collect();
        let mut threshold = vec![1.0; n];
        let mut alias: Vec<u32> = (0..n as u32).collect();
        let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| scaled[i] < 1.0);
        while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
            small.pop();
            threshold[s] = scaled[s];
            alias[s] = l as u32;
            scaled[l] -= 1.0 - scaled[s];
            if scaled[l] < 1.0 {
                large.pop();
                small.push(l);
            }
        }
        // What remains is 1 up to rounding: those slots keep their own item.
        for i in small.into_iter().chain(large) {
            threshold[i] = 1.0;
            alias[i] = i as u32;
        }
        AliasTable { prob, threshold, alias }
    }

    /// The probability of each item under the table (for checking it): (1/n) sum over slots.
    pub fn implied_probabilities(&self) -> Vec<f64> {
        let n = self.prob.len();
        let mut p = vec![0.0; n];
        for i in 0..n {
            p[i] += self.threshold[i] / n as f64;
            p[self.alias[i] as usize] += (1.0 - self.threshold[i]) / n as f64;
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_alias_table_reproduces_its_weights() {
        for weights in [vec![1.0], vec![1.0, 2.0, 3.0, 4.0], vec![0.0, 5.0, 0.0, 1e-9, 7.0], vec![0.0, 0.0]] {
            let t = AliasTable::new(&weights);
            for (a, b) in t.implied_probabilities().iter().zip(&t.prob) {
                assert!((a - b).abs() < 1e-12, "{weights:?}: {a} vs {b}");
            }
        }
    }
}
