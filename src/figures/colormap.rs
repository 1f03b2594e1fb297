//! Colour maps for false-colour images: magma (perceptually uniform; the table FLIP ships).

use std::sync::OnceLock;

/// Magma's 256 entries.
fn magma() -> &'static [[u8; 3]] {
    static TABLE: OnceLock<Vec<[u8; 3]>> = OnceLock::new();
    TABLE.get_or_init(|| nv_flip::magma_lut().to_vec().chunks(3).map(|c| [c[0], c[1], c[2]]).collect())
}

/// Magma at t in [0, 1] (clamped; NaN maps to 0).
pub fn magma_at(t: f64) -> [u8; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    magma()[(t * 255.0).round() as usize]
}
