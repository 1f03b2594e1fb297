//! The per-pixel accumulator as the GPU stores it (`AccumPixel` in `shaders/accum_pixel.wgsl`):
//! Kahan-compensated sums of the radiance samples and of their squares, the sample count and a
//! 64-bit ray count. The path tracer writes it, the viewer's display pass reads it, checkpoints
//! and split-render parts store it exactly. Its layout is checked against naga's reflection of
//! the WGSL (`tests/shader_layouts.rs`).

use bytemuck::{Pod, Zeroable};

/// Per-pixel accumulator. `sum - sum_err` and `sum_sq - sum_sq_err` are the exact sums (Kahan's
/// err holds minus the low-order part not yet in the sum).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct AccumPixel {
    pub sum: [f32; 3],
    pub count: u32,
    pub sum_err: [f32; 3],
    /// Rays traced for this pixel (camera, bounce and shadow), low and high 32 bits.
    pub rays_lo: u32,
    pub sum_sq: [f32; 3],
    pub rays_hi: u32,
    pub sum_sq_err: [f32; 3],
    /// Samples in which a researcher's technique faulted (`shaders/technique.wgsl`): each
    /// contributed 0.
    pub faults: u32,
}

impl AccumPixel {
    /// Rays traced for this pixel so far.
    pub fn rays(&self) -> u64 {
        (self.rays_hi as u64) << 32 | self.rays_lo as u64
    }

    /// The first of `pixels` that does not hold exactly `spp` samples (its 32-bit count is spp
    /// modulo 2^32): a driver that dropped work, or a file that does not match its header.
    pub fn first_miscounted(pixels: &[AccumPixel], spp: u64) -> Option<usize> {
        pixels.iter().position(|p| p.count as u64 != spp % (1 << 32))
    }

    /// The compensated sums as f64: (sum of samples, sum of squares) per channel.
    pub fn exact_sums(&self) -> ([f64; 3], [f64; 3]) {
        (
            std::array::from_fn(|c| self.sum[c] as f64 - self.sum_err[c] as f64),
            std::array::from_fn(|c| self.sum_sq[c] as f64 - self.sum_sq_err[c] as f64),
        )
    }
}
