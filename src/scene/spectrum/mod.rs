//! Spectra, turned into the linear sRGB colours pathlab renders with, exactly as Mitsuba 3's RGB
//! variants turn them (`Properties::get_texture_impl` and `spectrum_list_to_srgb` in Mitsuba's
//! `src/core/properties.cpp` and `src/core/spectrum.cpp`).
//!
//! How a spectrum becomes a colour depends on what it is for ([`SpectrumRole`]):
//! - a **reflectance** (`get_texture`): the spectrum times the D65 illuminant, integrated against
//!   the CIE 1931 matching functions, to XYZ, to linear sRGB, clamped to [0, 1];
//! - an **unbounded** quantity (`get_unbounded_texture`: a conductor's `eta` and `k`): the same,
//!   clamped below at 0 only;
//! - an **emission** (`get_emissive_texture`: radiance, intensity, irradiance): without the D65
//!   weight, clamped below at 0. A uniform spectrum of value v emits v times the sRGB colour of
//!   XYZ = (1, 1, 1), a slightly purple white (Mitsuba does this so that its RGB and spectral
//!   variants agree), where a reflectance of v is grey v.
//!
//! A blackbody (`<spectrum type="blackbody">`) is a spectrum Mitsuba's RGB variants cannot
//! evaluate; pathlab gives it the colour Mitsuba's spectral variants integrate: Planck's law in
//! W m^-2 sr^-1 nm^-1, as an emission.

mod cie_tables;

use cie_tables::{CIE_D65, CIE_XYZ};

/// Mitsuba's `MI_CIE_MIN` and `MI_CIE_MAX`: the range of its CIE tables, in nm.
pub const CIE_MIN: f64 = 360.0;
pub const CIE_MAX: f64 = 830.0;
/// Mitsuba's `MI_CIE_Y_NORMALIZATION`: a unit spectrum integrates to luminance 1.
const CIE_Y_NORMALIZATION: f64 = 1.0 / 106.750_259_399_414_062_5;
/// The steps of `spectrum_list_to_srgb`'s Riemann sum over [CIE_MIN, CIE_MAX].
const STEPS: usize = 1000;

/// What a spectrum is for: Mitsuba converts each role differently.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpectrumRole {
    /// A BSDF's reflectance or transmittance, a texture's colour: bounded to [0, 1].
    Reflectance,
    /// A conductor's `eta` or `k`: any value >= 0.
    Unbounded,
    /// An emitter's radiance, intensity or irradiance.
    Emission,
}

/// A spectrum as a scene file gives it.
#[derive(Debug, Clone, PartialEq)]
pub enum Spectrum {
    /// One value at every wavelength (`<spectrum value="0.5"/>`).
    Uniform(f64),
    /// Values at increasing wavelengths in nm, linear between them, zero outside
    /// (`<spectrum value="400:0.1, 500:0.5"/>`).
    Sampled { wavelengths: Vec<f64>, values: Vec<f64> },
    /// Planck's law at `temperature` kelvin, zero outside [min, max] nm.
    Blackbody { temperature: f64, min: f64, max: f64 },
}

/// A spectrum's colour, and whether it was clamped into its role's range (Mitsuba warns).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Converted {
    pub rgb: [f64; 3],
    /// The colour before clamping, where it was out of gamut.
    pub clamped_from: Option<[f64; 3]>,
}

/// Why a spectrum's text or values are not a spectrum (Mitsuba's checks).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpectrumError {
    #[error("`{0}` is not a number or a wavelength:value pair")]
    NotAPair(String),
    #[error("a spectrum needs at least two wavelength:value pairs")]
    TooFew,
    #[error("wavelengths must increase ({0} nm follows {1} nm)")]
    NotIncreasing(f64, f64),
    #[error("{0} is not a finite number")]
    NotFinite(f64),
}

impl Spectrum {
    /// Parses Mitsuba's `value` attribute: one number, or `wavelength:value` pairs separated by
    /// commas or white space.
    pub fn parse(text: &str) -> Result<Spectrum, SpectrumError> {
        let tokens: Vec<&str> = text.split(|c: char| c == ',' || c.is_whitespace()).filter(|t| !t.is_empty()).collect();
        let number = |t: &str| -> Result<f64, SpectrumError> {
            let v: f64 = t.trim().parse().map_err(|_| SpectrumError::NotAPair(t.to_string()))?;
            if v.is_finite() { Ok(v) } else { Err(SpectrumError::NotFinite(v)) }
        };
        if tokens.len() == 1 && !tokens[0].contains(':') {
            return Ok(Spectrum::Uniform(number(tokens[0])?));
        }
        let mut wavelengths = Vec::with_capacity(tokens.len());
        let mut values = Vec::with_capacity(tokens.len());
        for t in tokens {
            let Some((w, v)) = t.split_once(':') else { return Err(SpectrumError::NotAPair(t.to_string())) };
            wavelengths.push(number(w)?);
            values.push(number(v)?);
        }
        Spectrum::sampled(wavelengths, values)
    }

    /// A sampled spectrum, checked as Mitsuba checks it: two pairs or more, wavelengths
    /// strictly increasing.
    pub fn sampled(wavelengths: Vec<f64>, values: Vec<f64>) -> Result<Spectrum, SpectrumError> {
        if wavelengths.len() < 2 {
            return Err(SpectrumError::TooFew);
        }
        for w in wavelengths.windows(2) {
            if w[1] <= w[0] {
                return Err(SpectrumError::NotIncreasing(w[1], w[0]));
            }
        }
        Ok(Spectrum::Sampled { wavelengths, values })
    }

    /// The linear sRGB colour Mitsuba's RGB variants give this spectrum in `role`.
    pub fn to_srgb(&self, role: SpectrumRole) -> Converted {
        match self {
            Spectrum::Uniform(v) => match role {
                // `uniform` texture: the value in every channel.
                SpectrumRole::Reflectance | SpectrumRole::Unbounded => Converted { rgb: [*v; 3], clamped_from: None },
                // `srgb` of v xyz_to_srgb(1, 1, 1), Mitsuba's f32 product.
                SpectrumRole::Emission => {
                    let white = xyz_to_srgb_f32([1.0; 3]);
                    Converted { rgb: white.map(|c| f64::from((*v as f32) * c as f32)), clamped_from: None }
                }
            },
            Spectrum::Sampled { wavelengths, values } => {
                let xyz = integrate_xyz(|w| {
                    if w < wavelengths[0] || w > wavelengths[wavelengths.len() - 1] {
                        return None;
                    }
                    // The interval [w0, w1] holding w (Mitsuba's `find_interval`: the last i
                    // with wavelengths[i] <= w, at most len - 2), and the linear interpolant.
                    let i = wavelengths.partition_point(|x| *x <= w).saturating_sub(1).min(wavelengths.len() - 2);
                    let (w0, w1, v0, v1) = (wavelengths[i], wavelengths[i + 1], values[i], values[i + 1]);
                    Some(((w - w1) * v0 + (w0 - w) * v1) / (w0 - w1))
                }, role != SpectrumRole::Emission);
                clamp(xyz_to_srgb(xyz), role)
            }
            Spectrum::Blackbody { temperature, min, max } => {
                let xyz = integrate_xyz(|w| (w >= *min && w <= *max).then(|| planck(w, *temperature)), false);
                clamp(xyz_to_srgb(xyz), SpectrumRole::Emission)
            }
        }
    }
}

/// Mitsuba's `spectrum_list_to_srgb` sum: XYZ = (CIE_MAX - CIE_MIN) / STEPS
/// * sum over STEPS wavelengths w of x̄ȳz̄(w) s(w) (D65(w) for a reflectance), times the
/// luminance normalisation. `s` is None outside the spectrum's range (no term).
fn integrate_xyz(s: impl Fn(f64) -> Option<f64>, d65: bool) -> [f64; 3] {
    let mut xyz = [0.0f64; 3];
    for i in 0..STEPS {
        let w = CIE_MIN + (i as f64 / (STEPS - 1) as f64) * (CIE_MAX - CIE_MIN);
        let Some(v) = s(w) else { continue };
        let (cmf, illuminant) = cie_at(w);
        let weight = v * if d65 { illuminant } else { 1.0 };
        for c in 0..3 {
            xyz[c] += cmf[c] * weight;
        }
    }
    xyz.map(|c| c * (CIE_MAX - CIE_MIN) * CIE_Y_NORMALIZATION / STEPS as f64)
}

/// The CIE matching functions and normalised D65 at w nm, linear between Mitsuba's 5 nm
/// samples (its `cie1931_xyz` and `cie_d65`); zero outside [CIE_MIN, CIE_MAX].
fn cie_at(w: f64) -> ([f64; 3], f64) {
    if !(CIE_MIN..=CIE_MAX).contains(&w) {
        return ([0.0; 3], 0.0);
    }
    let n = CIE_XYZ.len();
    let t = (w - CIE_MIN) * ((n - 1) as f64 / (CIE_MAX - CIE_MIN));
    let i0 = (t as usize).min(n - 2);
    let w1 = t - i0 as f64;
    let w0 = 1.0 - w1;
    let lerp = |a: f32, b: f32| w0 * f64::from(a) + w1 * f64::from(b);
    let xyz = [0, 1, 2].map(|c| lerp(CIE_XYZ[i0][c], CIE_XYZ[i0 + 1][c]));
    (xyz, lerp(CIE_D65[i0], CIE_D65[i0 + 1]))
}

/// Mitsuba's XYZ to linear sRGB (Rec. 709 primaries, D65 white) matrix, as f32.
const XYZ_TO_SRGB: [[f32; 3]; 3] = [
    [3.240479, -1.537150, -0.498535],
    [-0.969256, 1.875991, 0.041556],
    [0.055648, -0.204043, 1.057311],
];

fn xyz_to_srgb(xyz: [f64; 3]) -> [f64; 3] {
    XYZ_TO_SRGB.map(|row| (0..3).map(|c| f64::from(row[c]) * xyz[c]).sum())
}

fn xyz_to_srgb_f32(xyz: [f32; 3]) -> [f32; 3] {
    XYZ_TO_SRGB.map(|row| (0..3).map(|c| row[c] * xyz[c]).sum())
}

/// Clamps into the role's range: [0, 1] for a reflectance, >= 0 otherwise.
fn clamp(rgb: [f64; 3], role: SpectrumRole) -> Converted {
    let bounded = role == SpectrumRole::Reflectance;
    let out = rgb.iter().any(|c| *c < 0.0 || (bounded && *c > 1.0));
    let clamped = rgb.map(|c| if bounded { c.clamp(0.0, 1.0) } else { c.max(0.0) });
    Converted { rgb: clamped, clamped_from: out.then_some(rgb) }
}

/// Planck's law: spectral radiance of a black body at `temperature` K and wavelength `nm`, in
/// W m^-2 sr^-1 nm^-1, with Mitsuba's constants (`src/spectra/blackbody.cpp`).
fn planck(nm: f64, temperature: f64) -> f64 {
    const C: f64 = 2.997_924_58e8;
    const H: f64 = 6.626_070_04e-34;
    const K: f64 = 1.380_648_52e-23;
    let (c0, c1) = (2.0 * H * C * C, H * C / K);
    let lambda = nm * 1e-9;
    1e-9 * c0 / (lambda.powi(5) * ((c1 / (lambda * temperature)).exp() - 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_uniform_and_pairs_and_refuses_what_mitsuba_refuses() {
        assert_eq!(Spectrum::parse(" 0.5 ").unwrap(), Spectrum::Uniform(0.5));
        assert_eq!(
            Spectrum::parse("400:0.1, 500:0.5 600:0.9").unwrap(),
            Spectrum::Sampled { wavelengths: vec![400.0, 500.0, 600.0], values: vec![0.1, 0.5, 0.9] }
        );
        assert_eq!(Spectrum::parse("400:0.1"), Err(SpectrumError::TooFew));
        assert_eq!(Spectrum::parse("500:0.1, 400:0.2"), Err(SpectrumError::NotIncreasing(400.0, 500.0)));
        assert!(matches!(Spectrum::parse("400:a, 500:1"), Err(SpectrumError::NotAPair(_))));
        assert!(matches!(Spectrum::parse("400, 500"), Err(SpectrumError::NotAPair(_))));
    }

    /// A unit spectrum integrates to luminance 1 (Mitsuba's normalisation), and D65 is white.
    #[test]
    fn a_unit_reflectance_is_white() {
        let white = Spectrum::Sampled { wavelengths: vec![CIE_MIN, CIE_MAX], values: vec![1.0, 1.0] }.to_srgb(SpectrumRole::Reflectance);
        for c in white.clamped_from.unwrap_or(white.rgb) {
            assert!((c - 1.0).abs() < 2e-3, "{white:?}");
        }
    }
}
