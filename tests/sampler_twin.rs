//! The WGSL samplers, run on the GPU, against their CPU twin (`pathlab::sequences`), at
//! ordinary and extreme sample indices (up to 2^32 - 1) and dimensions (past the Halton table).
//! Integer-only paths (independent, Sobol') must agree bit for bit; Halton's final float
//! division may differ by an ulp on GPUs whose division is not correctly rounded.

use crate::common;

use common::gpu;
use pathlab::gpu::KernelRun;
use pathlab::method::Sampler;
use pathlab::sequences;
use pathlab::shaders::{self, bindings};

const KERNEL: &str = r#"
struct Query { pixel: u32, index: u32, dim: u32, seed: u32 }
@group(0) @binding(0) var<storage, read> queries: array<Query>;
@group(0) @binding(1) var<storage, read_write> results: array<f32>;

@compute @workgroup_size(64)
fn sample_kernel(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x;
    if (i >= arrayLength(&queries)) {
        return;
    }
    let q = queries[i];
    results[i] = sample_1d(q.pixel, q.index, q.dim, q.seed);
}
"#;

fn queries() -> Vec<[u32; 4]> {
    let indices = [0u32, 1, 2, 3, 17, 1000, 65535, 65536, 1 << 24, (1 << 31) + 5, u32::MAX - 2, u32::MAX - 1, u32::MAX];
    let dims = [0u32, 1, 2, 3, 5, 17, 64, 254, 255, 256, 300];
    let mut q = Vec::new();
    for (k, &index) in indices.iter().enumerate() {
        for &dim in &dims {
            q.push([k as u32 * 7919 + dim, index, dim, 0x5eed ^ k as u32]);
        }
    }
    q
}

fn gpu_samples(sampler: Sampler, queries: &[[u32; 4]]) -> Vec<f32> {
    let source = shaders::assemble(&shaders::LIBRARY, KERNEL);
    let run = KernelRun {
        source: &source,
        entry: "sample_kernel",
        constants: &[("SAMPLER", sampler.constant() as f64)],
        inputs: vec![(0, bytemuck::cast_slice(queries).to_vec())],
        uniforms: vec![(bindings::HALTON_PRIMES.number, shaders::halton_primes_bytes())],
        texel_tables: vec![],
        output: (1, (queries.len() * 4) as u64),
        workgroups: (queries.len() as u32).div_ceil(64),
    };
    bytemuck::pod_collect_to_vec(&run.run(gpu()).expect("sampler kernel"))
}

#[test]
fn wgsl_samplers_match_their_cpu_twin() {
    let q = queries();
    for sampler in Sampler::ALL {
        let gpu = gpu_samples(sampler, &q);
        for (i, &[pixel, index, dim, seed]) in q.iter().enumerate() {
            let cpu = sequences::sample_1d(sampler, pixel, index, dim, seed);
            let g = gpu[i];
            assert!((0.0..1.0).contains(&g), "{sampler:?} index {index} dim {dim}: {g} outside [0, 1)");
            let ulps = (g.to_bits() as i64 - cpu.to_bits() as i64).abs();
            // Where the adapter's arithmetic is the CPU's (lavapipe): Halton's radical inverse
            // within one ulp, the others exact. A GPU may round division by 2.5 ulps and fuse
            // multiply-adds (WGSL allows both): 8 ulps. Halton's rotation x + shift - 1 is
            // rounded at the sum's scale: an ulp of x there is an ulp of [1, 2), 2^-23, after the
            // wrap however small the result (an NVIDIA H200: 0.0009738207 against 0.0009737015),
            // so the rotated samples are compared by their distance on the circle [0, 1).
            let cpu_arithmetic = crate::common::gpu().info.device_type == wgpu::DeviceType::Cpu;
            let halton = matches!(sampler, Sampler::Halton | Sampler::HaltonScrambled);
            let allowed = match (halton, cpu_arithmetic) {
                (true, true) => 1,
                (false, true) => 0,
                (_, false) => 8,
            };
            let d = (g as f64 - cpu as f64).abs();
            let circle = d.min(1.0 - d);
            let rotated_close = sampler == Sampler::Halton && !cpu_arithmetic && circle <= 2.0 * f32::EPSILON as f64;
            assert!(ulps <= allowed || rotated_close, "{sampler:?} index {index} dim {dim}: gpu {g} cpu {cpu}");
        }
    }
}

/// Near 2^32 the samples are still distinct and well spread (no index overflow folding
/// consecutive indices onto the same point).
#[test]
fn indices_near_two_to_the_32_stay_distinct() {
    let q: Vec<[u32; 4]> = (0..64u32).map(|k| [3, u32::MAX - k, 1, 9]).collect();
    for sampler in Sampler::ALL {
        let mut s = gpu_samples(sampler, &q);
        s.sort_by(f32::total_cmp);
        s.dedup();
        assert!(s.len() >= 60, "{sampler:?}: only {} distinct values of 64", s.len());
    }
}
