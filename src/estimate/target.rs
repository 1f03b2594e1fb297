//! What a render can be asked to reach instead of a sample count: an estimated relMSE or
//! display PSNR (`render --target-rel-error E` / `--target-psnr DB`, `advise`). The loop that
//! renders to it is `render::to_target`.

use serde::Serialize;

use super::ErrorEstimate;

/// What to reach.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Target {
    /// Estimated relMSE at or below this.
    RelMse(f64),
    /// Estimated display PSNR at or above this (dB).
    Psnr(f64),
}

impl Target {
    /// Whether `e` meets the target.
    pub fn reached(&self, e: &ErrorEstimate) -> bool {
        match *self {
            Target::RelMse(t) => e.rel_mse <= t,
            Target::Psnr(db) => e.psnr.is_some_and(|p| p >= db),
        }
    }

    /// How many times the current samples the target needs, assuming error ~ 1/spp.
    pub fn remaining_factor(&self, e: &ErrorEstimate) -> f64 {
        match *self {
            Target::RelMse(t) => e.rel_mse / t,
            Target::Psnr(db) => e.psnr.map_or(f64::INFINITY, |p| 10f64.powf((db - p) / 10.0)),
        }
    }
}

