//! How next event estimation picks among the lights: the default selection, the luminance
//! that weighs a light's power, and the alias table power selection draws from
//! (`shaders/light_table.wgsl`).

use glam::DVec3;

use crate::scene::Scene;
use crate::method::LightSelect;

/// The Rec. 709 luminance weights of linear sRGB (Mitsuba's `luminance`): the one definition,
/// generated into the WGSL as `LUMINANCE` (src/shaders/generated.rs).
pub const LUMINANCE_WEIGHTS: [f64; 3] = [0.212671, 0.715160, 0.072169];

/// Rec. 709 luminance, the weight of a colour in power selection.
pub fn luminance(c: DVec3) -> f64 {
    c.dot(DVec3::from(LUMINANCE_WEIGHTS))
}

impl Scene {
    /// The light selection of a method that leaves it open (the one place it is decided):
    /// `power` for scenes with emissive meshes (a mesh of a thousand triangles is a thousand
    /// lights), else `all`, which keeps the images of sphere-lit scenes as they were.
    pub fn default_light_select(&self) -> LightSelect {
        if self.has_triangle_lights() { LightSelect::Power } else { LightSelect::All }
    }

    /// The lights of the table (`sampled_lights`) and power selection's alias table over them:
    /// the one place the table's weights are decided.
    pub fn light_selection(&self, sample_environment: bool) -> (Vec<super::Light>, AliasTable) {
        let lights = self.sampled_lights(sample_environment);
        let weights: Vec<f64> = lights.iter().map(|&l| self.light_power(l)).collect();
        let table = AliasTable::new(&weights);
        (lights, table)
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

    /// Whether the table, as the kernel reads it (f32), draws exactly as uniform selection does:
    /// every item's probability 1/n and every slot keeping its own item.
    pub fn draws_uniformly_in_f32(&self) -> bool {
        let n = self.prob.len().max(1) as f32;
        self.prob.iter().zip(&self.threshold).all(|(&p, &t)| p as f32 == 1.0 / n && t as f32 == 1.0)
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
