//! The chi-square goodness-of-fit harness of sampling routines, run on the GPU, after Mitsuba
//! 3's `chi2.py` and pbrt-v4's `bsdfs_test.cpp`: the kernel's own WGSL sampler against its own
//! WGSL pdf. `tests/chi2_sampling.rs` proves the built-in strategies with it, and `technique`
//! a researcher's.
//!
//! A test kernel draws N directions with the routine under test. The host bins them on a
//! 101 x 202 grid over (phi, s = 1 - cos theta) in the routine's frame (fine s bins where the
//! density lives, coarse ones elsewhere, with s = 1 and any support boundary on bin edges),
//! integrates the routine's pdf over every cell (4 x 4 Gauss-Legendre points, evaluated on the
//! GPU), pools cells expecting fewer than 5 samples, and computes the chi-square p-value. Hard
//! failures (`Chi2Failure`), whatever the p-value: a non-finite sample, a sample in a cell
//! whose integrated pdf is 0, total pdf mass off by more than 1e-3, a reported pdf that differs
//! from the pdf function at the sampled direction, a weight that differs from eval * cos / pdf,
//! a fault of a researcher's technique, an integrand that is not 0 where the pdf is.

use std::f64::consts::PI;

use crate::gpu::{Gpu, GpuError, Kernel, KernelData, KernelLayout};
use crate::shaders;

/// Cells in phi and in s, by default (`Routine::bins`).
pub const PHI_BINS: usize = 101;
pub const S_BINS: usize = 202;
pub const DEFAULT_BINS: (usize, usize) = (PHI_BINS, S_BINS);

/// 4-point Gauss-Legendre nodes and weights on [-1, 1].
pub const GAUSS_LEGENDRE_4: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
];

/// Test kernel: the routine's `routine_sample`, `routine_pdf` and `routine_integrand` are
/// spliced in per test.
pub const KERNEL: &str = r#"
struct TestParams { count: u32, seed: u32, _p0: u32, _p1: u32 }
struct Drawn { sample: vec4f, check: vec4f }
@group(0) @binding(0) var<storage, read> test_params: TestParams;
@group(0) @binding(1) var<storage, read_write> test_out: array<vec4f>;
@group(0) @binding(2) var<storage, read> test_dirs: array<vec4f>;

@compute @workgroup_size(64)
fn sample_main(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x;
    if (i >= test_params.count) {
        return;
    }
    let s = test_params.seed;
    let u = vec2f(sample_independent(i, 0u, 0u, s), sample_independent(i, 0u, 1u, s));
    technique_faults = 0u;
    var drawn = routine_sample(u, sample_independent(i, 0u, 2u, s));
    if (technique_faults != 0u) {
        drawn.check.w = f32(technique_faults);
    }
    test_out[2u * i] = drawn.sample;
    test_out[2u * i + 1u] = drawn.check;
}

@compute @workgroup_size(64)
fn pdf_main(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x;
    if (i >= arrayLength(&test_dirs)) {
        return;
    }
    technique_faults = 0u;
    let pdf = routine_pdf(test_dirs[i].xyz);
    test_out[i] = vec4f(pdf, routine_integrand(test_dirs[i].xyz), f32(technique_faults), 0.0);
}
"#;

/// A sampling routine under test.
#[derive(Debug, Clone)]
pub struct Routine {
    pub name: String,
    /// WGSL defining `routine_sample(u: vec2f, u_lobe: f32) -> Drawn` (direction and reported
    /// pdf in `sample`; `check.x` = relative error of the weight, 0 when not applicable;
    /// `check.y` = 1 for a sample lost (in no cell: its probability is the pdf's missing mass);
    /// `check.z` = the sample's estimate f / p of `routine_integrand`'s integral, 0 if none)
    /// and `routine_pdf(d: vec3f) -> f32`, both in a frame whose +z is the binning axis;
    /// optionally `routine_integrand(d: vec3f) -> f32` (see `integrand`).
    pub wgsl: String,
    pub constants: Vec<(&'static str, f64)>,
    /// Fine s bins cover [0, s_split]; coarse ones (s_split, 2]. Negative: bins spaced
    /// geometrically from -s_split to 2 (after one [0, -s_split]), for lobes far narrower than
    /// their tails (a microfacet lobe of alpha 1e-3 has GGX's tails).
    pub s_split: f64,
    /// Relative tolerance of a sample's reported pdf against the pdf function at the sampled
    /// direction (as written out, in f32): 1e-4, more for lobes so narrow that the direction's
    /// rounding moves the density, or whose half vector cancels. A sample's weight is held to
    /// it too where it is above 1e-4: the same rounding moves the BSDF's value (a lobe sampled
    /// in a frame that is not the routine's, as a normal map's, is evaluated at the direction
    /// after its round trip through the world: 1.0e-4 relative, measured, for a rough plastic).
    pub pdf_tolerance: f64,
    /// The density below which `pdf_tolerance` applies to this floor instead (an absolute
    /// tolerance for small densities): where a routine is binned in another frame than its
    /// own, the direction's round trip moves a density that vanishes at a boundary (the cosine
    /// lobe at the horizon) by ~1e-7 absolute, a large relative change. 1e-30: none.
    pub pdf_floor: f64,
    /// The BSDF data the routine's material reads (bound at `bindings::BSDF_DATA`; empty: none).
    pub bsdf_data: Vec<f32>,
    /// The environment map the routine reads (`EnvironmentMap::pack`, bound at
    /// `bindings::ENVIRONMENT_MAP`; empty: none). The routine then runs in the whole path
    /// tracer's module, where the map's functions are.
    pub environment_map: Vec<f32>,
    /// Cells in phi and in s: `DEFAULT_BINS`, or a grid whose edges fall on a piecewise-constant
    /// density's (an environment map's texels).
    pub bins: (usize, usize),
    /// Whether the support check runs: a cell point where `routine_integrand` (the function
    /// whose integral the samples estimate, `check.z`) is above 1e-3 of its largest value and
    /// the pdf is 0 is then a hard failure (a strategy that can never draw where the integrand lives). Where `wgsl`
    /// does not define `routine_integrand`, the harness defines it as 0.
    pub integrand: bool,
}

/// Why a routine fails, whatever its p-value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Chi2Failure {
    #[error("the test kernel failed: {0}")]
    Kernel(String),
    #[error("its pdf is {pdf} at the direction {direction:?}, not a finite number >= 0")]
    BadPdf { pdf: f64, direction: [f32; 3] },
    #[error("its pdf integrates to {mass:.6} over the sphere, not 1 (a wrongly normalised pdf)")]
    Mass { mass: f64 },
    #[error("its pdf integrates to {mass:.6} over the sphere, more than 1")]
    MassAboveOne { mass: f64 },
    #[error("{count} of its samples fall where its pdf is 0 (first: cell {cell}, direction {direction:?})")]
    OutsideSupport { count: u64, cell: usize, direction: [f32; 3] },
    #[error("a sample is not finite: {sample:?}")]
    NonFinite { sample: [f32; 4] },
    #[error("a sampled direction has length {length}, not 1")]
    NotUnit { length: f64 },
    #[error("a sample reports pdf {reported}, but its pdf function gives {function} at {direction:?}")]
    ReportedPdf { reported: f64, function: f64, direction: [f32; 3] },
    #[error("a sample's weight differs from eval * cos / pdf by {0} (relative)")]
    Weight(f64),
    #[error("{count} of {total} samples faulted ({what})")]
    Faults { count: u64, total: u64, what: String },
    #[error("its pdf is 0 where the integrand is {integrand} (direction {direction:?}): it can never sample there, so it misses part of the integral")]
    Uncovered { integrand: f64, direction: [f32; 3] },
}

/// The binned outcome of one routine.
#[derive(Debug, Clone)]
pub struct Chi2Outcome {
    pub p_value: f64,
    /// Samples per cell (row-major: s bin, then phi bin), then the lost samples.
    pub observed: Vec<u64>,
    /// Expected samples per cell (times N), then the lost cell's.
    pub expected: Vec<f64>,
    /// The s bin edges.
    pub s_edges: Vec<f64>,
    /// Cells in phi and in s.
    pub bins: (usize, usize),
    /// The pdf's integral over the sphere.
    pub mass: f64,
    /// Mean and standard error of the samples' estimates (`check.z`).
    pub estimate: (f64, f64),
    /// The first hard failure found once the samples were binned (then `p_value` is 0 where
    /// a sample lies outside the support).
    pub failure: Option<Chi2Failure>,
}

/// The chi-square p-value of `observed` counts against `expected` probabilities (times `n`
/// samples), cells expecting fewer than 5 pooled into one. A sample in a cell of probability 0
/// is a failure.
pub fn pooled_chi_square(expected: &[f64], observed: &[u64], n: f64) -> Result<f64, (usize, u64)> {
    let (mut chi2, mut dof, mut pooled_exp, mut pooled_obs) = (0.0, 0usize, 0.0, 0.0);
    let mut outside: Option<(usize, u64)> = None;
    for (c, &e) in expected.iter().enumerate() {
        let (e, o) = (e * n, observed[c] as f64);
        if e == 0.0 {
            if o != 0.0 {
                let first = outside.map_or(c, |(f, _)| f);
                outside = Some((first, outside.map_or(0, |(_, k)| k) + observed[c]));
            }
        } else if e < 5.0 {
            pooled_exp += e;
            pooled_obs += o;
        } else {
            chi2 += (o - e) * (o - e) / e;
            dof += 1;
        }
    }
    if let Some(o) = outside {
        return Err(o);
    }
    if pooled_exp > 0.0 {
        chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
        dof += 1;
    }
    Ok(crate::stats::chi2_sf(chi2, dof.saturating_sub(1).max(1)))
}

/// `s_bins` s bin edges: three quarters fine and the rest coarse (150 + 52 of 202), or uniform
/// (then s = 1 is an edge for an even count).
pub fn s_edges(s_split: f64, s_bins: usize) -> Vec<f64> {
    if s_split < 0.0 {
        let s_min = -s_split;
        let mut e = vec![0.0];
        e.extend((0..s_bins).map(|i| s_min * (2.0 / s_min).powf(i as f64 / (s_bins - 1) as f64)));
        *e.last_mut().unwrap() = 2.0;
        return e;
    }
    if s_split >= 2.0 {
        return (0..=s_bins).map(|i| 2.0 * i as f64 / s_bins as f64).collect();
    }
    let fine = s_bins * 150 / S_BINS;
    let coarse = s_bins - fine;
    let mut e: Vec<f64> = (0..=fine).map(|i| s_split * i as f64 / fine as f64).collect();
    e.extend((1..=coarse).map(|i| s_split + (2.0 - s_split) * i as f64 / coarse as f64));
    e
}

/// The unit direction at (phi, s = 1 - cos theta) about +z.
pub fn direction(phi: f64, s: f64) -> [f64; 3] {
    let cos = 1.0 - s;
    let sin = (s * (2.0 - s)).max(0.0).sqrt();
    [sin * phi.cos(), sin * phi.sin(), cos]
}

/// (phi, s) of a unit direction, s = 1 - cos computed without cancellation near +z.
pub fn phi_s(d: [f64; 3]) -> (f64, f64) {
    let phi = d[1].atan2(d[0]).rem_euclid(2.0 * PI);
    let rho2 = d[0] * d[0] + d[1] * d[1];
    let s = if d[2] > 0.0 { rho2 / (1.0 + d[2]) } else { 1.0 - d[2] };
    (phi, s)
}

/// The routine's WGSL and the harness's kernel, on the sampling library (with the techniques
/// `techniques` in their kinds' places).
pub fn source(routine: &Routine, techniques: shaders::TechniqueFiles) -> String {
    let integrand = if routine.wgsl.contains("fn routine_integrand(") { "" } else { "fn routine_integrand(d: vec3f) -> f32 { return 0.0; }\n" };
    let parts: &[(&str, &str)] = if routine.environment_map.is_empty() { &shaders::LIBRARY } else { &shaders::PATH_TRACER };
    shaders::assemble_with(parts, &format!("{}\n{integrand}{KERNEL}", routine.wgsl), crate::accel::BRUTE_FORCE_TRIANGLES, techniques)
}

/// The routine's kernel, compiled once: its sampling entry (`sample_main`) and its pdf entry
/// (`pdf_main`), dispatched as often as a test needs.
pub struct RoutineKernel<'a> {
    kernel: Kernel,
    routine: &'a Routine,
}

impl<'a> RoutineKernel<'a> {
    /// Compiles `source` (`source(routine, ..)`, or a kernel of the caller's with `entries`) for
    /// the routine's constants, with its BSDF data and environment map bound.
    pub fn new(gpu: &Gpu, source: &str, routine: &'a Routine, entries: &[&str], inputs: &[u32]) -> Result<Self, GpuError> {
        let mut storage = inputs.to_vec();
        storage.extend(Self::data(routine).iter().map(|(b, _)| *b));
        let layout = KernelLayout { storage: &storage, uniforms: &[], texel_tables: &[], output: 1 };
        Ok(RoutineKernel { kernel: Kernel::new(gpu, source, entries, &routine.constants, &layout)?, routine })
    }

    /// The routine's own data bindings: its BSDF data and environment map, where it has them.
    fn data(routine: &Routine) -> Vec<(u32, &[u8])> {
        let mut data = Vec::new();
        if !routine.bsdf_data.is_empty() {
            data.push((shaders::bindings::BSDF_DATA.number, bytemuck::cast_slice(&routine.bsdf_data)));
        }
        if !routine.environment_map.is_empty() {
            data.push((shaders::bindings::ENVIRONMENT_MAP.number, bytemuck::cast_slice(&routine.environment_map)));
        }
        data
    }

    /// Runs `entry` over `items` invocations with `inputs` (binding, bytes) and returns its
    /// output of `out_vec4s` vec4s (binding 1).
    pub fn run(&self, gpu: &Gpu, entry: &str, inputs: &[(u32, &[u8])], out_vec4s: usize, items: usize) -> Result<Vec<[f32; 4]>, GpuError> {
        let mut storage = inputs.to_vec();
        storage.extend(Self::data(self.routine));
        let data = KernelData { storage: &storage, uniforms: &[], texel_tables: &[] };
        self.kernel.dispatch(gpu, entry, &data, (out_vec4s * 16) as u64, (items as u32).div_ceil(64))
    }
}

/// Runs `entry` of the routine's kernel over `items` invocations and returns its output
/// (a kernel compiled for this one dispatch).
pub fn run(gpu: &Gpu, source: &str, routine: &Routine, entry: &str, inputs: Vec<(u32, Vec<u8>)>, out_vec4s: usize, items: usize) -> Result<Vec<[f32; 4]>, GpuError> {
    let numbers: Vec<u32> = inputs.iter().map(|(b, _)| *b).collect();
    let slices: Vec<(u32, &[u8])> = inputs.iter().map(|(b, bytes)| (*b, bytes.as_slice())).collect();
    RoutineKernel::new(gpu, source, routine, &[entry], &numbers)?.run(gpu, entry, &slices, out_vec4s, items)
}

/// What a fault flag (`TECHNIQUE_FAULT_*` bits) means.
pub fn describe_faults(bits: u32) -> String {
    let mut what = Vec::new();
    if bits & shaders::flags::TECHNIQUE_FAULT_VALUE != 0 {
        what.push("a non-finite or negative number, a direction that is not unit, or a point off the light");
    }
    if bits & shaders::flags::TECHNIQUE_FAULT_LOOP != 0 {
        what.push("a loop stopped after TECHNIQUE_MAX_ITERATIONS iterations");
    }
    what.join("; ")
}

/// Quadrature points of the cells a support boundary crosses, at most (`binned`).
const REFINED_POINTS: usize = 1 << 21;

/// Runs one chi-square test of `samples` samples; returns the binned outcome, or the first
/// hard failure.
pub fn chi_square(gpu: &Gpu, routine: &Routine, techniques: shaders::TechniqueFiles, samples: u32, seed: u32) -> Result<Chi2Outcome, Chi2Failure> {
    let mut outcome = binned(gpu, routine, techniques, samples, seed)?;
    match outcome.failure.take() {
        Some(f) => Err(f),
        None => Ok(outcome),
    }
}

/// `chi_square`, returning the binned samples with a failure found after binning (to draw
/// them); failures before (a kernel, a fault, a bad pdf) are errors.
pub fn binned(gpu: &Gpu, routine: &Routine, techniques: shaders::TechniqueFiles, samples: u32, seed: u32) -> Result<Chi2Outcome, Chi2Failure> {
    let source = source(routine, techniques);
    let kernel = |e: GpuError| Chi2Failure::Kernel(e.to_string());
    let params: [u32; 4] = [samples, seed, 0, 0];
    // One module, two pipelines: the pdf's serves the cells and, where a support boundary
    // crosses some, their sub-cells.
    let compiled = RoutineKernel::new(gpu, &source, routine, &["sample_main", "pdf_main"], &[0, 2]).map_err(kernel)?;
    let params_bytes: &[u8] = bytemuck::cast_slice(&params);
    let drawn = compiled.run(gpu, "sample_main", &[(0, params_bytes)], 2 * samples as usize, samples as usize).map_err(kernel)?;

    // Faults of a researcher's technique come first: nothing else about such samples means much.
    let faulted: Vec<u32> = drawn.chunks(2).map(|pair| pair[1][3] as u32).filter(|&f| f != 0).collect();
    if !faulted.is_empty() {
        let bits = faulted.iter().fold(0, |a, &b| a | b);
        return Err(Chi2Failure::Faults { count: faulted.len() as u64, total: samples as u64, what: describe_faults(bits) });
    }

    let (phi_bins, s_bins) = routine.bins;
    let edges = s_edges(routine.s_split, s_bins);
    let dphi = 2.0 * PI / phi_bins as f64;
    // Gauss-Legendre points of every cell, then the sampled directions (pdf consistency).
    let gl = GAUSS_LEGENDRE_4;
    let mut points: Vec<[f32; 4]> = Vec::with_capacity(phi_bins * s_bins * 16 + samples as usize);
    let mut weights = Vec::with_capacity(phi_bins * s_bins * 16);
    for j in 0..s_bins {
        let (s0, s1) = (edges[j], edges[j + 1]);
        for i in 0..phi_bins {
            let phi0 = i as f64 * dphi;
            for (xs, ws) in gl {
                for (xp, wp) in gl {
                    let s = s0 + (s1 - s0) * (xs + 1.0) / 2.0;
                    let phi = phi0 + dphi * (xp + 1.0) / 2.0;
                    let d = direction(phi, s);
                    points.push([d[0] as f32, d[1] as f32, d[2] as f32, 0.0]);
                    weights.push(ws * wp * (s1 - s0) * dphi / 4.0);
                }
            }
        }
    }
    let cell_points = points.len();
    points.extend(drawn.iter().step_by(2).map(|d| [d[0], d[1], d[2], 0.0]));
    let pdfs = compiled.run(gpu, "pdf_main", &[(0, params_bytes), (2, bytemuck::cast_slice(&points))], points.len(), points.len()).map_err(kernel)?;
    let faulted = pdfs.iter().filter(|p| p[2] != 0.0).count() as u64;
    if faulted > 0 {
        let bits = pdfs.iter().fold(0u32, |a, p| a | p[2] as u32);
        return Err(Chi2Failure::Faults { count: faulted, total: points.len() as u64, what: format!("{} (in its pdf)", describe_faults(bits)) });
    }

    let mut expected = vec![0.0f64; phi_bins * s_bins];
    // The support check ignores integrand values below 1e-3 of its largest: where it vanishes
    // continuously (the rim of a light's visible cap), f32 may round the pdf to 0 first.
    let negligible = 1e-3 * pdfs[..cell_points].iter().map(|p| p[1] as f64).fold(0.0, f64::max);
    for (k, w) in weights.iter().enumerate() {
        let p = pdfs[k][0] as f64;
        let d = points[k];
        if !(p.is_finite() && p >= 0.0) {
            return Err(Chi2Failure::BadPdf { pdf: p, direction: [d[0], d[1], d[2]] });
        }
        let integrand = pdfs[k][1] as f64;
        if routine.integrand && p == 0.0 && integrand > negligible {
            return Err(Chi2Failure::Uncovered { integrand, direction: [d[0], d[1], d[2]] });
        }
        expected[k / 16] += w * p;
    }
    // Cells a support boundary may cross (the pdf 0 at some quadrature points of the cell and
    // its eight neighbours, not at others: a boundary can pass between a cell's points) are
    // integrated again on sub-cells: 4 x 4 points integrate a density smooth
    // over the cell, not one that drops to 0 inside it (the error is of the order of the jump
    // times the cell's area; a density bounded to part of a cap, as Eto and Tokuyoshi's
    // normals, lost 0.15% of its mass to it over 101 x 202 cells, and its samples fell in cells
    // whose points all missed the support).
    let (zero, positive): (Vec<bool>, Vec<bool>) = (0..phi_bins * s_bins)
        .map(|c| {
            let p = &pdfs[16 * c..16 * c + 16];
            (p.iter().any(|x| x[0] == 0.0), p.iter().any(|x| x[0] > 0.0))
        })
        .unzip();
    let crossed: Vec<usize> = (0..phi_bins * s_bins)
        .filter(|&c| {
            let (j, i) = ((c / phi_bins) as isize, (c % phi_bins) as isize);
            let around = (-1..=1).flat_map(|dj| (-1..=1).map(move |di| (j + dj, (i + di).rem_euclid(phi_bins as isize))));
            let cells: Vec<usize> = around.filter(|&(j, _)| j >= 0 && j < s_bins as isize).map(|(j, i)| j as usize * phi_bins + i as usize).collect();
            cells.iter().any(|&n| zero[n]) && cells.iter().any(|&n| positive[n])
        })
        .collect();
    if !crossed.is_empty() {
        // 16 x 16 sub-cells, fewer where many cells are crossed (a boundary that crosses the
        // binning frame's rows, as the horizon of a frame turned to a mirror direction): at most
        // REFINED_POINTS points in all, within one dispatch.
        let refine = ((REFINED_POINTS as f64 / (16 * crossed.len()) as f64).sqrt() as usize).clamp(2, 16);
        let (mut sub_points, mut sub_weights) = (Vec::new(), Vec::new());
        for &c in &crossed {
            let (j, i) = (c / phi_bins, c % phi_bins);
            let (ds, dp) = ((edges[j + 1] - edges[j]) / refine as f64, dphi / refine as f64);
            for a in 0..refine {
                for b in 0..refine {
                    let (s0, phi0) = (edges[j] + a as f64 * ds, i as f64 * dphi + b as f64 * dp);
                    for (xs, ws) in gl {
                        for (xp, wp) in gl {
                            let d = direction(phi0 + dp * (xp + 1.0) / 2.0, s0 + ds * (xs + 1.0) / 2.0);
                            sub_points.push([d[0] as f32, d[1] as f32, d[2] as f32, 0.0]);
                            sub_weights.push(ws * wp * ds * dp / 4.0);
                        }
                    }
                }
            }
        }
        let sub_pdfs = compiled.run(gpu, "pdf_main", &[(0, params_bytes), (2, bytemuck::cast_slice(&sub_points))], sub_points.len(), sub_points.len()).map_err(kernel)?;
        let per_cell = refine * refine * 16;
        for (n, &c) in crossed.iter().enumerate() {
            let range = n * per_cell..(n + 1) * per_cell;
            expected[c] = 0.0;
            for k in range {
                let p = sub_pdfs[k][0] as f64;
                if !(p.is_finite() && p >= 0.0) || sub_pdfs[k][2] != 0.0 {
                    let d = sub_points[k];
                    return Err(Chi2Failure::BadPdf { pdf: p, direction: [d[0], d[1], d[2]] });
                }
                expected[c] += sub_weights[k] * p;
            }
        }
    }
    let mass: f64 = expected.iter().sum();
    // Samples the routine flags as lost (check.y = 1: a microfacet reflected below the surface)
    // fill one more cell, whose probability is the pdf's missing mass.
    let lost = drawn.chunks(2).filter(|pair| pair[1][1] != 0.0).count() as u64;
    let mut failure = None;
    if lost == 0 {
        if (mass - 1.0).abs() > 1e-3 {
            failure = Some(Chi2Failure::Mass { mass });
        }
    } else if mass > 1.0 + 1e-3 {
        failure = Some(Chi2Failure::MassAboveOne { mass });
    }
    expected.push((1.0 - mass).max(0.0));

    let mut observed = vec![0u64; phi_bins * s_bins + 1];
    let weight_tolerance = routine.pdf_tolerance.max(1e-4) as f32;
    *observed.last_mut().unwrap() = lost;
    let (mut sum, mut sum_sq) = (0.0f64, 0.0f64);
    for (n, pair) in drawn.chunks(2).enumerate() {
        let (d, check) = (pair[0], pair[1]);
        let estimate = check[2] as f64;
        sum += estimate;
        sum_sq += estimate * estimate;
        if check[1] != 0.0 {
            // A lost sample may still be checked: a delta lobe's direction and weight.
            if !d.iter().all(|x| x.is_finite()) {
                failure = failure.or(Some(Chi2Failure::NonFinite { sample: d }));
                continue;
            }
            if check[0] > weight_tolerance {
                failure = failure.or(Some(Chi2Failure::Weight(check[0] as f64)));
            }
            continue;
        }
        if !(d.iter().all(|x| x.is_finite()) && check[0].is_finite() && check[2].is_finite()) {
            failure = failure.or(Some(Chi2Failure::NonFinite { sample: d }));
            continue;
        }
        let dir = [d[0] as f64, d[1] as f64, d[2] as f64];
        let len = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
        if (len - 1.0).abs() >= 1e-5 {
            failure = failure.or(Some(Chi2Failure::NotUnit { length: len }));
            continue;
        }
        let (phi, s) = phi_s(dir.map(|x| x / len));
        let i = ((phi / dphi) as usize).min(phi_bins - 1);
        let j = edges.partition_point(|&e| e <= s).clamp(1, s_bins) - 1;
        // The pdf the routine reports equals its pdf function at the sampled direction.
        let (reported, function) = (d[3] as f64, pdfs[cell_points + n][0] as f64);
        let cell = j * phi_bins + i;
        if expected[cell] == 0.0 && function > 0.0 {
            // A cell whose quadrature points all miss the support, which the sample's own
            // density says it reaches (a support boundary across the cell, not on its edges):
            // counted with the lost samples, whose cell holds the mass the quadrature misses.
            *observed.last_mut().unwrap() += 1;
        } else {
            // (Where the pdf is 0 at the sample too, the chi-square names the cell.)
            observed[cell] += 1;
        }
        if (reported - function).abs() > routine.pdf_tolerance * function.abs().max(routine.pdf_floor) {
            failure = failure.or(Some(Chi2Failure::ReportedPdf { reported, function, direction: [d[0], d[1], d[2]] }));
        }
        if check[0] > weight_tolerance {
            failure = failure.or(Some(Chi2Failure::Weight(check[0] as f64)));
        }
    }
    let n = samples as f64;
    let mean = sum / n;
    let std_err = ((sum_sq / n - mean * mean).max(0.0) / (n - 1.0)).sqrt();

    let p_value = match pooled_chi_square(&expected, &observed, n) {
        Ok(p) => p,
        Err((cell, count)) => {
            let (j, i) = (cell / phi_bins, cell % phi_bins);
            let d = if j < s_bins { direction((i as f64 + 0.5) * dphi, 0.5 * (edges[j] + edges[j + 1])) } else { [f64::NAN; 3] };
            // The support comes before the mass: samples where the pdf is 0 say more.
            failure = Some(Chi2Failure::OutsideSupport { count, cell, direction: d.map(|x| x as f32) }).or(failure);
            0.0
        }
    };
    Ok(Chi2Outcome { p_value, observed, expected: expected.iter().map(|e| e * n).collect(), s_edges: edges, mass, estimate: (mean, std_err), failure, bins: routine.bins })
}
