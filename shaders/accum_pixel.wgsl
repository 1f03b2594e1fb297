// accum_pixel.wgsl — the per-pixel accumulator layout (`AccumPixel` in src/film/accum_pixel.rs),
// shared by the path tracer (accumulate.wgsl writes it) and the viewer's display pass (reads it).
//
// `sum` and `sum_sq` are Kahan-compensated sums of the radiance samples and of their squares;
// `*_err` hold minus the low-order parts not yet in them, so the exact sums are `sum - sum_err`.

struct AccumPixel {
    sum: vec3f,
    count: u32,
    sum_err: vec3f,
    // Rays traced for this pixel (camera, bounce and shadow rays), as a 64-bit count.
    rays_lo: u32,
    sum_sq: vec3f,
    rays_hi: u32,
    sum_sq_err: vec3f,
    // Samples in which a researcher's technique faulted (technique.wgsl): each contributed 0.
    faults: u32,
}
