//! The display transform: linear radiance to the [0, 1] values a screen shows. One place for
//! PNG previews, image grids and the display-referred metrics (PSNR, SSIM, FLIP); and what an
//! image area shows (`view`).
//!
//! `v = encode(clip(x * 2^exposure, 0, 1))`, with `encode` the sRGB transfer function or a
//! plain power `x^(1/G)` (the study displayed its images through gamma 1.6).

mod view;

use std::fmt;
use std::str::FromStr;

pub use view::{View, LOG10_RANGE};

use crate::film::Film;

/// How linear radiance is encoded for display.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Transfer {
    /// The sRGB transfer function (IEC 61966-2-1).
    Srgb,
    /// `x^(1/G)` after clipping to [0, 1].
    Gamma(f32),
}

/// Transfer function and exposure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DisplayTransform {
    pub transfer: Transfer,
    /// Scale by 2^exposure before clipping.
    pub exposure: f32,
}

impl Default for DisplayTransform {
    fn default() -> Self {
        DisplayTransform { transfer: Transfer::Srgb, exposure: 0.0 }
    }
}

#[derive(Debug, thiserror::Error, PartialEq)]
#[error("display transform `{0}`: expected `srgb` or `gamma:G` with G a positive number")]
pub struct TransferParseError(pub String);

impl FromStr for Transfer {
    type Err = TransferParseError;
    fn from_str(s: &str) -> Result<Transfer, TransferParseError> {
        let bad = || TransferParseError(s.to_string());
        match s.trim().to_ascii_lowercase().as_str() {
            "srgb" => Ok(Transfer::Srgb),
            other => {
                let g: f32 = other.strip_prefix("gamma:").ok_or_else(bad)?.trim().parse().map_err(|_| bad())?;
                if g.is_finite() && g > 0.0 { Ok(Transfer::Gamma(g)) } else { Err(bad()) }
            }
        }
    }
}

impl Transfer {
    /// The display pass's code of this transfer function (`TRANSFER_*` in display.wgsl).
    pub const fn code(self) -> u32 {
        match self {
            Transfer::Srgb => 0,
            Transfer::Gamma(_) => 1,
        }
    }
}

impl fmt::Display for Transfer {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Transfer::Srgb => write!(f, "srgb"),
            Transfer::Gamma(g) => write!(f, "gamma:{g}"),
        }
    }
}

impl fmt::Display for DisplayTransform {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.exposure == 0.0 { write!(f, "{}", self.transfer) } else { write!(f, "{}, exposure {:+} stops", self.transfer, self.exposure) }
    }
}

/// sRGB transfer function of a value in [0, 1].
fn srgb_encode(x: f32) -> f32 {
    if x <= 0.0031308 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 }
}

impl DisplayTransform {
    /// Display value in [0, 1] of one linear channel (non-finite values show as 0).
    pub fn apply(&self, x: f32) -> f32 {
        let x = x * self.exposure.exp2();
        let x = if x.is_finite() { x.clamp(0.0, 1.0) } else { 0.0 };
        match self.transfer {
            Transfer::Srgb => srgb_encode(x),
            Transfer::Gamma(g) => x.powf(1.0 / g),
        }
    }

    /// The film's mean as a display image.
    pub fn film(&self, film: &Film) -> DisplayImage {
        DisplayImage {
            width: film.width,
            height: film.height,
            pixels: film.mean.iter().map(|p| p.map(|c| self.apply(c))).collect(),
        }
    }
}

/// A display-referred RGB image, values in [0, 1], row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct DisplayImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 3]>,
}

impl DisplayImage {
    /// 8-bit quantisation (round to nearest), as a PNG stores it.
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.pixels.iter().flat_map(|p| p.map(|c| (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_and_apply() {
        assert_eq!("srgb".parse::<Transfer>(), Ok(Transfer::Srgb));
        assert_eq!("gamma:1.6".parse::<Transfer>(), Ok(Transfer::Gamma(1.6)));
        assert!("gamma:0".parse::<Transfer>().is_err());
        assert!("gamma".parse::<Transfer>().is_err());
        assert!("linear".parse::<Transfer>().is_err());
        let gamma = DisplayTransform { transfer: Transfer::Gamma(2.0), exposure: 0.0 };
        assert!((gamma.apply(0.25) - 0.5).abs() < 1e-7);
        assert_eq!(gamma.apply(4.0), 1.0);
        assert_eq!(gamma.apply(-1.0), 0.0);
        assert_eq!(gamma.apply(f32::NAN), 0.0);
        let srgb = DisplayTransform::default();
        assert!((srgb.apply(0.5) - 0.735_356_6).abs() < 1e-6);
        let brighter = DisplayTransform { exposure: 1.0, ..srgb };
        assert_eq!(brighter.apply(0.25), srgb.apply(0.5));
    }
}
