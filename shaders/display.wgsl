// display.wgsl — the viewer's display pass: one band of accumulators to the shown image, on the
// device (no readback). Per pixel: the mean of the samples, then either the display transform
// (exposure, clip, sRGB or gamma encoding: src/display.rs) or a false-colour error value on a
// log10 scale through the magma colour map (src/figures/colormap.rs, the same table).

// What a pixel shows (`View` in src/viewer/display_pass.rs).
const VIEW_RADIANCE: u32 = 0u;
const VIEW_REL_STDERR: u32 = 1u;
const VIEW_ABS_ERROR: u32 = 2u;
const VIEW_REL_ERROR: u32 = 3u;

const TRANSFER_SRGB: u32 = 0u;

// The epsilon of relMSE (src/metrics/linear.rs: REL_MSE_EPSILON).
const REL_EPSILON: f32 = 0.01;

struct DisplayParams {
    width: u32,
    // First image row of this band, and its rows.
    y0: u32,
    rows: u32,
    view: u32,
    // 2^exposure.
    exposure_scale: f32,
    transfer: u32,
    // 1 / G of the gamma transfer.
    inv_gamma: f32,
    // The log10 range of the false colour: lo maps to the first entry of the map, hi to the last.
    log_lo: f32,
    log_hi: f32,
    // Texels between the starts of two rows of `shown` (the width, padded for the copy).
    row_stride: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(BINDING_DISPLAY_PARAMS) var<uniform> display: DisplayParams;
@group(0) @binding(BINDING_DISPLAY_BAND) var<storage, read> band: array<AccumPixel>;
// The reference image's linear RGB (w unused), row-major; one dummy texel without a reference.
@group(0) @binding(BINDING_DISPLAY_REFERENCE) var<storage, read> reference: array<vec4f>;
// Magma, 256 entries of linear [0, 1] display values.
@group(0) @binding(BINDING_DISPLAY_COLOUR_MAP) var<uniform> colour_map: array<vec4f, 256>;
// The shown image as packed RGBA8 (copied into the texture egui draws; a storage buffer, not a
// storage texture: llvmpipe writes buffers vectorised, texels one by one).
@group(0) @binding(BINDING_DISPLAY_SHOWN) var<storage, read_write> shown: array<u32>;

// sRGB transfer function (IEC 61966-2-1) of a value in [0, 1].
fn srgb_encode(x: vec3f) -> vec3f {
    let low = 12.92 * x;
    let high = 1.055 * pow(x, vec3f(1.0 / 2.4)) - 0.055;
    return select(high, low, x <= vec3f(0.0031308));
}

// The display transform: scale by 2^exposure, clip to [0, 1], encode.
fn display_transform(linear: vec3f) -> vec3f {
    let x = clamp(linear * display.exposure_scale, vec3f(0.0), vec3f(1.0));
    if display.transfer == TRANSFER_SRGB {
        return srgb_encode(x);
    }
    return pow(x, vec3f(display.inv_gamma));
}

// Magma at log10(v), clamped to the range; zero and NaN map to the first entry.
fn false_colour(v: f32) -> vec3f {
    let t = (log10_safe(v) - display.log_lo) / (display.log_hi - display.log_lo);
    let i = u32(round(clamp(select(0.0, t, t == t), 0.0, 1.0) * 255.0));
    return colour_map[i].rgb;
}

fn log10_safe(v: f32) -> f32 {
    return log2(max(v, 1e-30)) * 0.30102999566;
}

@compute @workgroup_size(8, 8)
fn display_main(@builtin(global_invocation_id) id: vec3u) {
    if id.x >= display.width || id.y >= display.rows {
        return;
    }
    // Fields are read one by one, not the whole 64-byte struct: only what the view needs
    // (a software rasteriser gathers every loaded word lane by lane).
    let i = id.y * display.width + id.x;
    let count = band[i].count;
    let y = display.y0 + id.y;
    var colour = vec3f(0.0);
    if count > 0u {
        let n = f32(count);
        // Mean of the samples, from the compensated sum.
        let mean = (band[i].sum - band[i].sum_err) / n;
        switch display.view {
            case VIEW_REL_STDERR: {
                // Variance of the mean: unbiased sample variance / n; relative to the squared
                // mean with its own variance removed (as the relMSE estimate does, src/estimate).
                var variance = vec3f(0.0);
                if count > 1u {
                    let s2 = max(((band[i].sum_sq - band[i].sum_sq_err) - n * mean * mean) / (n - 1.0), vec3f(0.0));
                    variance = s2 / n;
                }
                let rel = variance / (max(mean * mean - variance, vec3f(0.0)) + REL_EPSILON);
                colour = false_colour(sqrt((rel.x + rel.y + rel.z) / 3.0));
            }
            case VIEW_ABS_ERROR: {
                let d = abs(mean - reference[y * display.width + id.x].xyz);
                colour = false_colour((d.x + d.y + d.z) / 3.0);
            }
            case VIEW_REL_ERROR: {
                // Per-pixel relative squared error, the terms of relMSE.
                let r = reference[y * display.width + id.x].xyz;
                let e = (mean - r) * (mean - r) / (r * r + REL_EPSILON);
                colour = false_colour((e.x + e.y + e.z) / 3.0);
            }
            default: {
                colour = display_transform(mean);
            }
        }
    }
    shown[y * display.row_stride + id.x] = pack4x8unorm(vec4f(colour, 1.0));
}
