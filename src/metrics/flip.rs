//! FLIP (Andersson et al. 2020, NVIDIA's perceptual difference evaluator), LDR variant,
//! through the `nv-flip` crate (the reference C++ implementation): the display images are
//! quantised to 8 bits, as a PNG holds them, and compared at 67 pixels per degree (FLIP's
//! default: a 0.7 m viewing distance from a 0.7 m wide 4K monitor). The score is the mean of
//! the per-pixel error map, as FLIP's tools report it.

use crate::display::DisplayImage;

/// Mean FLIP error of `test` against `reference` (0 = identical, 1 = maximal).
pub fn flip(reference: &DisplayImage, test: &DisplayImage) -> f64 {
    flip_map(reference, test).iter().map(|&e| e as f64).sum::<f64>() / reference.pixels.len().max(1) as f64
}

/// The per-pixel FLIP error map, row-major.
pub fn flip_map(reference: &DisplayImage, test: &DisplayImage) -> Vec<f32> {
    assert_eq!((reference.width, reference.height), (test.width, test.height), "flip: sizes differ");
    let image = |img: &DisplayImage| nv_flip::FlipImageRgb8::with_data(img.width, img.height, &img.to_rgb8());
    nv_flip::flip(image(reference), image(test), nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec()
}
