//! Bias verdicts a user can read. At the study's highest spp, the renders of every seed are
//! averaged (independent estimates: mean of means, variance / K^2) and tested against the
//! reference with the correctness suite's tools:
//!
//! 1. the image-mean bias per channel, z = bias / standard error (both images' variances),
//!    against a Šidák threshold over the 3 channels;
//! 2. the per-pixel z-test (`stats::z_test`; >= 99.75% of channels must pass a Šidák threshold
//!    over all channels), on pixel blocks that hold enough samples for a normal approximation
//!    (`block_for`): for methods that meet some of the scene's emission only by chance
//!    (`meets_emission_by_chance`: without light sampling; under an environment map, without
//!    importance sampling of the map under MIS), whose rare bright samples make per-pixel (or
//!    small-block) normal approximations invalid at a study's sample counts, blocks of 2^23
//!    samples where the image allows, at least 8 blocks; for the others, per pixel from 1024
//!    samples per pixel (spp x seeds) on, else blocks of at least 1024 samples (a variance
//!    estimated from a few dozen samples makes |z| heavy-tailed). Coarser than per pixel, such
//!    a verdict is weaker: raise --spp for a finer test.
//!
//! Each test runs at alpha / 2, with alpha = 0.01 shared by all methods of the study (Šidák), so
//! a whole study wrongly calls some unbiased method biased with probability below 0.01.

use serde::Serialize;

use crate::method::{EnvSampling, LightSampling, Method};
use crate::scene::Scene;
use crate::metrics::{mean_bias, ChannelBias, Z_TEST_MIN_PASS};
use crate::film::Film;
use crate::stats::{sidak, z_test, z_threshold};

use super::StudyMethod;

/// Family-wise false-alarm probability of one study's verdicts.
pub const STUDY_ALPHA: f64 = 0.01;
/// Confidence of the bias bounds quoted.
pub const CONFIDENCE: f64 = 0.99;

/// One method's verdict.
#[derive(Debug, Clone, Serialize)]
pub struct Verdict {
    pub method: Method,
    /// A deliberately biased demonstration method (expected to be flagged).
    pub biased_demonstration: bool,
    /// Samples per pixel per seed, and seeds averaged.
    pub spp: u64,
    pub seeds: usize,
    /// Per channel (R, G, B).
    pub bias: [ChannelBias; 3],
    /// Largest |z| of the image-mean bias over the channels, and its threshold.
    pub mean_bias_max_abs_z: f64,
    pub mean_bias_threshold: f64,
    /// Side of the pixel blocks of the z-test (1 = per pixel).
    pub block: u32,
    pub z_pass_fraction: f64,
    pub z_threshold: f64,
    /// Either test rejected "same expectation as the reference".
    pub bias_detected: bool,
    /// The sentence for the report.
    pub text: String,
}

/// Samples a block should hold for its mean to be near normal when light is found only by
/// chance. Measured on the study scene at 256x128: with cosine sampling, 32x32 blocks of 3000 spp
/// (3M samples) gave |z| up to 4.9 in three seeds alike (rare light hits: the sample variance
/// underestimates, the mean lags), while 30,000 spp in the same blocks gave |z| <= 2.7; so 2^23.
const BLOCK_SAMPLES: u64 = 1 << 23;
/// Samples a pixel (or block) must hold for the z-test of a method with light sampling: with
/// fewer, its variance is estimated from so few samples that |z| is heavy-tailed (Student's t
/// with few degrees of freedom, skewed by rare bright paths). Measured on the study scene at
/// 1024x512 against a 16384-spp `best` reference: per pixel at 30 samples (10 spp x 3 seeds),
/// nee, mis and best each failed 0.65% to 1.4% of pixels at |z| > 6.27 with image-mean biases
/// below 0.01%; the same renders in 8x8 blocks (1920 samples) pass.
const LIGHT_SAMPLED_BLOCK_SAMPLES: u64 = 1024;
/// Fewest blocks the block z-test keeps.
const MIN_BLOCKS: u32 = 8;

/// Whether `method` meets some of `scene`'s emission only by chance, in rare samples of large
/// weight: every light without light sampling; and under an environment map (whose bright
/// parts, a sun, hold most of its power in a small solid angle), unless next event estimation
/// samples the map by importance (`+env`, luminance or compensated) and MIS combines it with
/// BSDF sampling. Measured on `assets/scenes/sun_sky.xml` (quick study, 256 spp x 2 seeds,
/// 2x2 blocks): `mis`, `nee`, `nee+env` and both uniform strategies failed 0.3% to 6.4% of
/// blocks with every image-mean bias interval containing 0, `mis+env` and `+env-compensated`
/// none.
pub fn meets_emission_by_chance(scene: &Scene, method: &Method) -> bool {
    let mis = matches!(method.lights, LightSampling::Mis | LightSampling::MisBalance);
    let map_sampled = method.environment && (method.env_sampling != EnvSampling::Uniform || method.env_technique.is_some());
    method.lights == LightSampling::None || (scene.environment_map.as_ref().is_some_and(|m| !m.is_black()) && !(mis && map_sampled))
}

/// Side of the square pixel blocks of a method's z-test: for methods that meet emission by
/// chance (`meets_emission_by_chance`), the smallest power of two dividing both sides whose
/// blocks hold `BLOCK_SAMPLES` samples; for the others, `LIGHT_SAMPLED_BLOCK_SAMPLES` (per pixel
/// from 1024 spp on); never more than leaves `MIN_BLOCKS` blocks (then the largest such).
pub fn block_for(width: u32, height: u32, spp: u64, by_chance: bool) -> u32 {
    let wanted = if by_chance { BLOCK_SAMPLES } else { LIGHT_SAMPLED_BLOCK_SAMPLES };
    let candidates: Vec<u32> = (0..16)
        .map(|k| 1u32 << k)
        .filter(|&b| width % b == 0 && height % b == 0 && (width / b) * (height / b) >= MIN_BLOCKS)
        .collect();
    candidates.iter().copied().find(|&b| (b as u64).pow(2) * spp >= wanted).or(candidates.last().copied()).unwrap_or(1)
}

/// Tests the seed-averaged `film` of `method` on `scene` against `reference`;
/// `methods_in_study` sets the per-method significance.
pub fn verdict(scene: &Scene, method: &StudyMethod, films: &[Film], reference: &Film, methods_in_study: usize) -> Verdict {
    let film = Film::mean_of(films);
    let alpha = sidak(STUDY_ALPHA, methods_in_study.max(1));
    let bias = mean_bias(&film, reference);
    let mean_threshold = z_threshold(alpha / 2.0, 3);
    let max_abs_z = bias.iter().filter_map(|b| b.z()).map(f64::abs).fold(0.0, f64::max);
    let block = block_for(film.width, film.height, film.spp, meets_emission_by_chance(scene, &method.method));
    let z = if block > 1 { z_test(&reference.downsample(block), &film.downsample(block), alpha / 2.0) } else { z_test(reference, &film, alpha / 2.0) };
    let detected = max_abs_z > mean_threshold || z.pass_fraction < Z_TEST_MIN_PASS;
    let pct = |x: f64| format!("{:+.2}%", 100.0 * x);
    let text = if detected {
        let per_channel: Vec<String> = ["R", "G", "B"]
            .iter()
            .zip(&bias)
            .map(|(c, b)| format!("{c} {} (+-{:.2}%)", pct(b.relative()), 100.0 * b.relative_half_width(CONFIDENCE).unwrap_or(0.0)))
            .collect();
        // Blocks alone, the image mean agreeing: a local bias, or an estimator whose block means
        // are not yet near normal (next event estimation without MIS near lights or glossy
        // surfaces at a few hundred spp: README, "Study", item 5); more samples tell them apart.
        let label = if method.biased {
            "biased, as expected of this demonstration"
        } else if max_abs_z > mean_threshold {
            "BIASED"
        } else {
            "BIASED IN BLOCKS, or heavy-tailed (the image mean agrees; raise --spp to tell them apart)"
        };
        format!(
            "{}: mean bias {} at {:.0}% confidence; {:.2}% of {} fail the z-test (|z| > {:.2}){}",
            label,
            per_channel.join(", "),
            100.0 * CONFIDENCE,
            100.0 * (1.0 - z.pass_fraction),
            if block > 1 { format!("{block}x{block} blocks") } else { "pixels".to_string() },
            z.threshold,
            if max_abs_z > mean_threshold { format!("; image-mean |z| = {max_abs_z:.1}") } else { String::new() }
        )
    } else {
        let bound = bias
            .iter()
            .map(|b| b.relative().abs() + b.relative_half_width(CONFIDENCE).unwrap_or(f64::INFINITY))
            .fold(0.0, f64::max);
        format!(
            "no bias detected at this precision: |bias| < {:.2}% with {:.0}% confidence in every channel; {:.2}% of {} pass the z-test{}",
            100.0 * bound,
            100.0 * CONFIDENCE,
            100.0 * z.pass_fraction,
            if block > 1 { format!("{block}x{block} blocks") } else { "pixels".to_string() },
            if method.biased { " (a biased demonstration that this precision cannot expose: raise --spp)" } else { "" }
        )
    };
    Verdict {
        method: method.method,
        biased_demonstration: method.biased,
        spp: films[0].spp,
        seeds: films.len(),
        bias,
        mean_bias_max_abs_z: max_abs_z,
        mean_bias_threshold: mean_threshold,
        block,
        z_pass_fraction: z.pass_fraction,
        z_threshold: z.threshold,
        bias_detected: detected,
        text,
    }
}

#[cfg(test)]
mod tests {
    use super::{block_for, meets_emission_by_chance, verdict};
    use crate::film::Film;
    use crate::method::Method;
    use crate::scene::Scene;

    /// A verdict that blocks alone reject (the image mean agreeing) says it may be a heavy tail;
    /// one the image mean rejects says BIASED; neither, no bias.
    #[test]
    fn block_only_flags_are_worded_apart_from_a_biased_mean() {
        let scene = Scene::load(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.toml")).unwrap();
        let nee = super::StudyMethod::by_name("nee").unwrap();
        let (w, h) = (64u32, 32u32);
        // 1 everywhere, each pixel's mean with variance 1e-3, at 1024 spp: tested per pixel.
        let film = |value: &dyn Fn(usize) -> f32| Film { width: w, height: h, spp: 1024, mean: (0..(w * h) as usize).map(|i| [value(i); 3]).collect(), variance: vec![[1e-3; 3]; (w * h) as usize] };
        let reference = film(&|_| 1.0);
        let judge = |f: Film| verdict(&scene, &nee, &[f], &reference, 1);
        let same = judge(film(&|_| 1.0));
        assert!(!same.bias_detected && same.text.starts_with("no bias detected"), "{}", same.text);
        // 8 pixels 0.5 brighter, 8 darker (|z| 11 each, 0.78% of the channels): the mean agrees.
        let blocks = judge(film(&|i| if i < 8 { 1.5 } else if i < 16 { 0.5 } else { 1.0 }));
        assert!(blocks.bias_detected && blocks.text.starts_with("BIASED IN BLOCKS, or heavy-tailed"), "{}", blocks.text);
        // Every pixel 1% brighter: the image mean's |z| is 10.
        let mean = judge(film(&|_| 1.01));
        assert!(mean.bias_detected && mean.text.starts_with("BIASED:"), "{}", mean.text);
    }

    #[test]
    fn blocks_hold_enough_samples_and_leave_enough_blocks() {
        // By chance: 256x128 at 3000 spp: 64x64 blocks (12M samples each, 8 blocks).
        assert_eq!(block_for(256, 128, 3000, true), 64);
        // 256x128 at 15000 spp: 32x32 blocks hold 15M.
        assert_eq!(block_for(256, 128, 15000, true), 32);
        // 128x64 at 512 spp: 64x64 would hold more but leave 2 blocks; 32x32 leaves 8.
        assert_eq!(block_for(128, 64, 512, true), 32);
        // Plenty of samples: per pixel.
        assert_eq!(block_for(64, 32, 1 << 23, true), 1);
        // Odd sizes: only 1 divides.
        assert_eq!(block_for(37, 23, 100, true), 1);
        // Light sampling: per pixel from 1024 samples, 8x8 blocks at 30 (1920 samples).
        assert_eq!(block_for(256, 128, 5000, false), 1);
        assert_eq!(block_for(1024, 512, 30, false), 8);
    }

    #[test]
    fn emission_is_met_by_chance_without_light_sampling_or_importance_sampling_of_a_map_under_mis() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let study = Scene::load(root.join("assets/scenes/study.toml")).unwrap();
        let sky = Scene::load(root.join("assets/scenes/sun_sky.xml")).unwrap();
        let by_chance = |scene: &Scene, name: &str| meets_emission_by_chance(scene, &Method::from_name(name).unwrap());
        assert!(by_chance(&study, "plain") && by_chance(&study, "cosine"));
        assert!(!by_chance(&study, "nee") && !by_chance(&study, "mis") && !by_chance(&study, "best"));
        for name in ["plain", "nee", "mis", "nee+env", "nee+env+env-uniform", "mis+env+env-uniform"] {
            assert!(by_chance(&sky, name), "{name}");
        }
        for name in ["mis+env", "mis+env+env-compensated", "mis-balance+env", "best+env"] {
            assert!(!by_chance(&sky, name), "{name}");
        }
    }
}
