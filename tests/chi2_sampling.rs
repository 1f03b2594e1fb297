//! Chi-square goodness-of-fit tests of the WGSL sampling routines, run on the GPU (issue 3,
//! section 1), after Mitsuba 3's `chi2.py` and pbrt-v4's `bsdfs_test.cpp`.
//!
//! A test kernel draws 10^6 directions with the routine under test (the WGSL function the path
//! tracer uses). The host bins them on a 101 x 202 grid over (phi, s = 1 - cos theta) in the
//! routine's frame (fine s bins where the density lives, coarse ones elsewhere, with s = 1 and
//! any support boundary on bin edges), integrates the routine's own WGSL pdf over every cell
//! (4 x 4 Gauss-Legendre points, evaluated on the GPU), pools cells expecting fewer than 5
//! samples, and computes the chi-square p-value. Each test passes when p >= the Šidák-corrected
//! level for alpha = 0.01 over all chi-square tests here, so the whole file fails falsely with
//! probability below 0.01. Hard failures, whatever the p-value: a non-finite sample, a sample
//! in a cell whose integrated pdf is 0, total pdf mass off by more than 1e-3, a reported pdf
//! that differs from the pdf function at the sampled direction by more than 1e-4 (relative),
//! or a BSDF weight that differs from eval * cos / pdf.

mod common;

use std::f64::consts::PI;

use common::gpu;
use pathlab::gpu::KernelRun;
use pathlab::shaders;
use pathlab::stats::{chi2_sf, sidak};

const SAMPLES: u32 = 1_000_000;
const PHI_BINS: usize = 101;
const S_BINS: usize = 202;
const ALPHA: f64 = 0.01;

/// Test kernel: the routine's `routine_sample` and `routine_pdf` are spliced in per test.
const KERNEL: &str = r#"
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
    let drawn = routine_sample(u, sample_independent(i, 0u, 2u, s));
    test_out[2u * i] = drawn.sample;
    test_out[2u * i + 1u] = drawn.check;
}

@compute @workgroup_size(64)
fn pdf_main(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x;
    if (i >= arrayLength(&test_dirs)) {
        return;
    }
    test_out[i] = vec4f(routine_pdf(test_dirs[i].xyz), 0.0, 0.0, 0.0);
}
"#;

struct Routine {
    name: String,
    /// WGSL defining `routine_sample(u: vec2f, u_lobe: f32) -> Drawn` (direction and reported
    /// pdf in `sample`; `check.x` = relative error of the weight, 0 when not applicable) and
    /// `routine_pdf(d: vec3f) -> f32`, both in a frame whose +z is the binning axis.
    wgsl: String,
    constants: Vec<(&'static str, f64)>,
    /// Fine s bins cover [0, s_split]; coarse ones (s_split, 2].
    s_split: f64,
}

/// s bin edges: 150 fine + 52 coarse, or 202 uniform (then s = 1 is an edge).
fn s_edges(s_split: f64) -> Vec<f64> {
    if s_split >= 2.0 {
        return (0..=S_BINS).map(|i| 2.0 * i as f64 / S_BINS as f64).collect();
    }
    let (fine, coarse) = (150, S_BINS - 150);
    let mut e: Vec<f64> = (0..=fine).map(|i| s_split * i as f64 / fine as f64).collect();
    e.extend((1..=coarse).map(|i| s_split + (2.0 - s_split) * i as f64 / coarse as f64));
    e
}

fn direction(phi: f64, s: f64) -> [f64; 3] {
    let cos = 1.0 - s;
    let sin = (s * (2.0 - s)).max(0.0).sqrt();
    [sin * phi.cos(), sin * phi.sin(), cos]
}

/// (phi, s) of a unit direction, s = 1 - cos computed without cancellation near +z.
fn phi_s(d: [f64; 3]) -> (f64, f64) {
    let phi = d[1].atan2(d[0]).rem_euclid(2.0 * PI);
    let rho2 = d[0] * d[0] + d[1] * d[1];
    let s = if d[2] > 0.0 { rho2 / (1.0 + d[2]) } else { 1.0 - d[2] };
    (phi, s)
}

fn run(routine: &Routine, entry: &str, inputs: Vec<(u32, Vec<u8>)>, out_vec4s: usize, items: usize) -> Vec<[f32; 4]> {
    let source = shaders::assemble(&shaders::LIBRARY, &format!("{}\n{}", routine.wgsl, KERNEL));
    let run = KernelRun {
        source: &source,
        entry,
        constants: &routine.constants,
        inputs,
        uniforms: vec![],
        output: (1, (out_vec4s * 16) as u64),
        workgroups: (items as u32).div_ceil(64),
    };
    bytemuck::pod_collect_to_vec(&run.run(gpu()).unwrap_or_else(|e| panic!("{}: {e}", routine.name)))
}

/// Runs one chi-square test; returns its p-value, or panics on a hard failure.
fn chi_square(routine: &Routine, seed: u32) -> f64 {
    let name = &routine.name;
    let params: [u32; 4] = [SAMPLES, seed, 0, 0];
    let drawn = run(routine, "sample_main", vec![(0, bytemuck::cast_slice(&params).to_vec())], 2 * SAMPLES as usize, SAMPLES as usize);

    let edges = s_edges(routine.s_split);
    let dphi = 2.0 * PI / PHI_BINS as f64;
    // Gauss-Legendre points of every cell, then the sampled directions (pdf consistency).
    let gl = [(-0.861_136_311_594_052_6, 0.347_854_845_137_453_9), (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.339_981_043_584_856_3, 0.652_145_154_862_546_1), (0.861_136_311_594_052_6, 0.347_854_845_137_453_9)];
    let mut points: Vec<[f32; 4]> = Vec::with_capacity(PHI_BINS * S_BINS * 16 + SAMPLES as usize);
    let mut weights = Vec::with_capacity(PHI_BINS * S_BINS * 16);
    for j in 0..S_BINS {
        let (s0, s1) = (edges[j], edges[j + 1]);
        for i in 0..PHI_BINS {
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
    let pdfs = run(
        routine,
        "pdf_main",
        vec![(0, bytemuck::cast_slice(&params).to_vec()), (2, bytemuck::cast_slice(&points).to_vec())],
        points.len(),
        points.len(),
    );

    let mut expected = vec![0.0f64; PHI_BINS * S_BINS];
    for (k, w) in weights.iter().enumerate() {
        let p = pdfs[k][0] as f64;
        assert!(p.is_finite() && p >= 0.0, "{name}: pdf {p} at a cell point");
        expected[k / 16] += w * p;
    }
    let mass: f64 = expected.iter().sum();
    assert!((mass - 1.0).abs() <= 1e-3, "{name}: pdf integrates to {mass}, not 1");

    let mut observed = vec![0u64; PHI_BINS * S_BINS];
    for (n, pair) in drawn.chunks(2).enumerate() {
        let (d, check) = (pair[0], pair[1]);
        assert!(d.iter().all(|x| x.is_finite()) && check[0].is_finite(), "{name}: non-finite sample {d:?}");
        let dir = [d[0] as f64, d[1] as f64, d[2] as f64];
        let len = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
        assert!((len - 1.0).abs() < 1e-5, "{name}: direction of length {len}");
        let (phi, s) = phi_s(dir.map(|x| x / len));
        let i = ((phi / dphi) as usize).min(PHI_BINS - 1);
        let j = edges.partition_point(|&e| e <= s).clamp(1, S_BINS) - 1;
        observed[j * PHI_BINS + i] += 1;
        // The pdf the routine reports equals its pdf function at the sampled direction.
        let (reported, function) = (d[3] as f64, pdfs[cell_points + n][0] as f64);
        assert!(
            (reported - function).abs() <= 1e-4 * function.abs().max(1e-30),
            "{name}: sample reports pdf {reported}, pdf function gives {function} at {d:?}"
        );
        assert!(check[0] <= 1e-4, "{name}: weight differs from eval * cos / pdf by {} (relative)", check[0]);
    }

    // Chi-square with pooling of low-expectation cells.
    let n = SAMPLES as f64;
    let (mut chi2, mut dof, mut pooled_exp, mut pooled_obs) = (0.0, 0usize, 0.0, 0.0);
    for (c, &e) in expected.iter().enumerate() {
        let (e, o) = (e * n, observed[c] as f64);
        if e == 0.0 {
            assert!(o == 0.0, "{name}: {o} samples in cell {c}, where the pdf is 0");
        } else if e < 5.0 {
            pooled_exp += e;
            pooled_obs += o;
        } else {
            chi2 += (o - e) * (o - e) / e;
            dof += 1;
        }
    }
    if pooled_exp > 0.0 {
        chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
        dof += 1;
    }
    chi2_sf(chi2, dof.saturating_sub(1).max(1))
}

// ----- the routines under test -------------------------------------------------------------

fn warp(name: &str, sample: &str, pdf: &str, s_split: f64) -> Routine {
    Routine {
        name: name.to_string(),
        wgsl: format!(
            "fn routine_sample(u: vec2f, u_lobe: f32) -> Drawn {{ let d = {sample}; return Drawn(vec4f(d, routine_pdf(d)), vec4f(0.0)); }}\n\
             fn routine_pdf(d: vec3f) -> f32 {{ return {pdf}; }}\n"
        ),
        constants: vec![],
        s_split,
    }
}

fn phong_lobe(n: f64) -> Routine {
    let mut r = warp(
        &format!("phong lobe n={n}"),
        &format!("square_to_phong_lobe(u, {n:.1})"),
        &format!("pdf_phong_lobe(one_minus_cos_between(d, vec3f(0.0, 0.0, 1.0)), {n:.1})"),
        (20.0 / (n + 1.0)).min(2.0),
    );
    // The lobe's own sample must report the same density as its pdf function.
    r.wgsl = r.wgsl.replace("routine_pdf(d)), vec4f(0.0))", "pdf_phong_lobe(one_minus_cos_between(d, vec3f(0.0, 0.0, 1.0)), 0.0 + routine_n())), vec4f(0.0))");
    r.wgsl.push_str(&format!("fn routine_n() -> f32 {{ return {n:.1}; }}\n"));
    r
}

/// The BSDF mixture exactly as the path tracer samples it (`sample_bsdf` with
/// BSDF_SAMPLING = phong), for shading normal +z and incident angle `theta_o` (degrees).
fn mixture(kd: f64, ks: f64, n: f64, theta_o: f64) -> Routine {
    let (ld, ls) = (kd, ks); // grey: luminance = value
    let p_spec = ls / (ld + ls);
    let t = theta_o.to_radians();
    let common = format!(
        "fn routine_material() -> Phong {{ return Phong(vec3f({kd:.6}), vec3f({ks:.6}), {n:.1}, {p_spec:.8}); }}\n\
         fn routine_wo() -> vec3f {{ return vec3f({:.8}, 0.0, {:.8}); }}\n",
        t.sin(),
        t.cos()
    );
    Routine {
        name: format!("phong mixture kd={kd} ks={ks} n={n} theta_o={theta_o}"),
        wgsl: format!(
            "{common}\
             fn routine_sample(u: vec2f, u_lobe: f32) -> Drawn {{\n\
                 let m = routine_material(); let n_s = vec3f(0.0, 0.0, 1.0); let wo = routine_wo();\n\
                 let bs = sample_bsdf(m, n_s, wo, u, u_lobe);\n\
                 let expect = path_weight(eval_phong(m, n_s, wo, bs.wi), dot(bs.wi, n_s), bs.pdf);\n\
                 let err = max3(abs(bs.weight - expect)) / max(max3(abs(expect)), 1e-30);\n\
                 return Drawn(vec4f(bs.wi, bs.pdf), vec4f(err, 0.0, 0.0, 0.0));\n\
             }}\n\
             fn routine_pdf(d: vec3f) -> f32 {{ return pdf_bsdf(routine_material(), vec3f(0.0, 0.0, 1.0), routine_wo(), d); }}\n"
        ),
        constants: vec![("BSDF_SAMPLING", 3.0), ("HAS_SPECULAR", 1.0)],
        s_split: 2.0,
    }
}

/// Cone sampling of a unit-radius sphere at distance `ratio` along +z, seen from the origin.
fn cone(ratio: f64) -> Routine {
    let omc_max = {
        let s2 = 1.0 / (ratio * ratio);
        s2 / (1.0 + (1.0 - s2).sqrt())
    };
    Routine {
        name: format!("sphere light cone d/r={ratio}"),
        wgsl: format!(
            "const C: vec3f = vec3f(0.0, 0.0, {ratio:.6});\n\
             fn routine_sample(u: vec2f, u_lobe: f32) -> Drawn {{\n\
                 let ls = sample_sphere_light_cone(C, 1.0, vec3f(0.0), u);\n\
                 return Drawn(vec4f(ls.wi, ls.pdf), vec4f(0.0));\n\
             }}\n\
             fn routine_pdf(d: vec3f) -> f32 {{\n\
                 let omc = sphere_cone_one_minus_cos_max(length(C), 1.0);\n\
                 // Density of the cone inside it (the sphere is hit), 0 outside.\n\
                 return select(0.0, pdf_sphere_light(C, 1.0, vec3f(0.0), false, d), one_minus_cos_between(d, vec3f(0.0, 0.0, 1.0)) <= omc);\n\
             }}\n"
        ),
        constants: vec![],
        // The cone's boundary is (up to 1e-5 relative, for f32 rounding of samples drawn right
        // on it) a bin edge: every cell beyond must stay empty.
        s_split: omc_max * (1.0 + 1e-5),
    }
}

/// Area sampling of the unit sphere from a point inside it.
fn inside(x: [f64; 3]) -> Routine {
    Routine {
        name: format!("sphere light from inside at {x:?}"),
        wgsl: format!(
            "const X: vec3f = vec3f({:.6}, {:.6}, {:.6});\n\
             fn routine_sample(u: vec2f, u_lobe: f32) -> Drawn {{\n\
                 let ls = sample_sphere_light_area(vec3f(0.0), 1.0, X, u);\n\
                 return Drawn(vec4f(ls.wi, ls.pdf), vec4f(0.0));\n\
             }}\n\
             fn routine_pdf(d: vec3f) -> f32 {{ return pdf_sphere_light(vec3f(0.0), 1.0, X, true, d); }}\n",
            x[0], x[1], x[2]
        ),
        constants: vec![],
        s_split: 2.0,
    }
}

fn all_routines() -> Vec<Routine> {
    let mut r = vec![
        warp("uniform sphere", "square_to_uniform_sphere(u)", "pdf_uniform_sphere()", 2.0),
        warp("uniform hemisphere", "square_to_uniform_hemisphere(u)", "pdf_uniform_hemisphere(d.z)", 2.0),
        warp("cosine hemisphere", "square_to_cosine_hemisphere(u)", "pdf_cosine_hemisphere(d.z)", 2.0),
    ];
    r.extend([0.0, 1.0, 10.0, 40.0, 100.0, 3000.0, 1e5].map(phong_lobe));
    for (kd, ks) in [(0.8, 0.2), (0.5, 0.5), (0.1, 0.9)] {
        for theta in [0.0, 45.0, 85.0] {
            r.push(mixture(kd, ks, 20.0, theta));
        }
    }
    r.extend([1.0001, 1.05, 2.0, 10.0, 1e3, 1e5].map(cone));
    r.push(inside([0.0, 0.0, 0.0]));
    r.push(inside([0.3, -0.2, 0.5]));
    r
}

#[test]
fn every_sampling_routine_fits_its_pdf() {
    let routines = all_routines();
    let level = sidak(ALPHA, routines.len());
    let mut report = Vec::new();
    let mut failed = Vec::new();
    for (k, routine) in routines.iter().enumerate() {
        let p = chi_square(routine, 1000 + k as u32);
        report.push(format!("{}: p = {p:.4}", routine.name));
        if p < level {
            failed.push(routine.name.clone());
        }
    }
    println!("{}\n(level {level:.2e} per test)", report.join("\n"));
    assert!(failed.is_empty(), "chi-square rejects {failed:?}:\n{}", report.join("\n"));
}
