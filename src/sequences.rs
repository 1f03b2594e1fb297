//! CPU twin of `shaders/sampler.wgsl`: the same hashes, radical inverses and Owen-scrambled
//! Sobol' points, operation for operation, so that host tools and tests can reproduce any
//! sample the GPU draws. `tests/sampler_twin.rs` keeps the two equal on the GPU.

use crate::method::Sampler;
use crate::shaders::{primes, HALTON_DIMENSIONS};

pub fn hash_pcg(v: u32) -> u32 {
    let state = v.wrapping_mul(747796405).wrapping_add(2891336453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277803737);
    (word >> 22) ^ word
}

pub fn mix_bits(mut v: u32) -> u32 {
    v ^= v >> 16;
    v = v.wrapping_mul(0x85ebca6b);
    v ^= v >> 13;
    v = v.wrapping_mul(0xc2b2ae35);
    v ^ (v >> 16)
}

pub fn hash2(a: u32, b: u32) -> u32 {
    hash_pcg(b.wrapping_add(hash_pcg(a)))
}

pub fn hash4(a: u32, b: u32, c: u32, d: u32) -> u32 {
    hash_pcg(d.wrapping_add(hash_pcg(c.wrapping_add(hash_pcg(b.wrapping_add(hash_pcg(a)))))))
}

pub fn u32_to_unit_float(x: u32) -> f32 {
    (x >> 8) as f32 * 5.960_464_5e-8
}

/// Kensler's hashed permutation (as pbrt-v4's PermutationElement).
pub fn permutation_element(mut i: u32, l: u32, p: u32) -> u32 {
    let mut w = l - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    loop {
        i ^= p;
        i = i.wrapping_mul(0xe170893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | (p >> 27));
        i = i.wrapping_mul(0x6935fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dcb303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e501cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860a3df);
        i &= w;
        i ^= i >> 5;
        if i < l {
            break;
        }
    }
    (i.wrapping_add(p)) % l
}

struct DigitState {
    a: u32,
    prefix: u32,
}

fn reverse_digit_chunk(base: u32, scrambled: bool, seed: u32, state: &mut DigitState, place_before: f32) -> (u32, u32) {
    let limit = u32::MAX / base;
    let (mut value, mut place) = (0u32, 1u32);
    while !(place > limit || (state.a == 0 && (!scrambled || place_before * place as f32 >= 16777216.0))) {
        let next = state.a / base;
        let mut digit = state.a - next * base;
        if scrambled {
            digit = permutation_element(digit, base, mix_bits(seed ^ state.prefix));
        }
        state.prefix = state.prefix.wrapping_mul(base).wrapping_add(digit);
        value = value * base + digit;
        place *= base;
        state.a = next;
    }
    (value, place)
}

/// Radical inverse by integer digit reversal in two chunks (see sampler.wgsl).
pub fn radical_inverse(base: u32, a: u32, scrambled: bool, seed: u32) -> f32 {
    let mut state = DigitState { a, prefix: 0 };
    let hi = reverse_digit_chunk(base, scrambled, seed, &mut state, 1.0);
    let lo = reverse_digit_chunk(base, scrambled, seed, &mut state, hi.1 as f32);
    let value = (hi.0 as f32 + lo.0 as f32 / lo.1 as f32) / hi.1 as f32;
    value.min(1.0 - f32::EPSILON / 2.0)
}

/// The exact radical inverse (u64 digit reversal, f64), to check the chunked version.
pub fn radical_inverse_exact(base: u32, mut a: u32) -> f64 {
    let (mut reversed, mut place) = (0u64, 1u64);
    while a > 0 {
        reversed = reversed * base as u64 + (a % base) as u64;
        place *= base as u64;
        a /= base;
    }
    reversed as f64 / place as f64
}

fn laine_karras_permutation(x: u32, seed: u32) -> u32 {
    let mut x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50b47c);
    x ^= x.wrapping_mul(0xb82f1e52);
    x ^= x.wrapping_mul(0xc7afe638);
    x ^= x.wrapping_mul(0x8d22f6e6);
    x
}

pub fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    laine_karras_permutation(x.reverse_bits(), seed).reverse_bits()
}

pub fn sobol_component(index: u32, component: u32) -> u32 {
    if component == 0 {
        return index.reverse_bits();
    }
    let (mut x, mut v, mut bits) = (0u32, 0x8000_0000u32, index);
    while bits != 0 {
        if bits & 1 != 0 {
            x ^= v;
        }
        bits >>= 1;
        v ^= v >> 1;
    }
    x
}

/// Sample `dim` of sample `index` in `pixel`, as `sample_1d` in sampler.wgsl.
pub fn sample_1d(sampler: Sampler, pixel: u32, index: u32, dim: u32, seed: u32) -> f32 {
    let halton = (dim as usize) < HALTON_DIMENSIONS;
    match sampler {
        Sampler::Sobol => {
            let pair_seed = hash4(seed, pixel, dim >> 1, 0x50b01);
            let shuffled = nested_uniform_scramble(index, pair_seed);
            let component = dim & 1;
            u32_to_unit_float(nested_uniform_scramble(sobol_component(shuffled, component), hash2(pair_seed, component + 1)))
        }
        Sampler::Halton if halton => {
            let base = primes(HALTON_DIMENSIONS)[dim as usize];
            let x = if base == 2 { u32_to_unit_float(index.reverse_bits()) } else { radical_inverse(base, index, false, 0) };
            let y = x + u32_to_unit_float(hash4(seed, pixel, dim, 0xc9a7));
            if y >= 1.0 { y - 1.0 } else { y }
        }
        Sampler::HaltonScrambled if halton => {
            radical_inverse(primes(HALTON_DIMENSIONS)[dim as usize], index, true, hash4(seed, pixel, dim, 0x0e7a))
        }
        _ => u32_to_unit_float(hash4(seed, pixel, index, dim)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunked_radical_inverse_matches_exact_digit_reversal() {
        let indices = [0u32, 1, 2, 3, 7, 100, 12345, 1 << 20, u32::MAX / 3, u32::MAX - 1, u32::MAX];
        for &base in &[2u32, 3, 5, 7, 31, 257, 1619] {
            for &a in &indices {
                let got = radical_inverse(base, a, false, 0) as f64;
                let want = radical_inverse_exact(base, a);
                assert!((got - want).abs() <= 2e-7, "base {base} index {a}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn permutation_element_is_a_permutation() {
        for &l in &[2u32, 3, 5, 13, 1619] {
            for p in [0u32, 1, 0xdead_beef] {
                let mut seen: Vec<u32> = (0..l).map(|i| permutation_element(i, l, p)).collect();
                seen.sort();
                assert_eq!(seen, (0..l).collect::<Vec<_>>());
            }
        }
    }

    #[test]
    fn scrambled_radical_inverse_is_uniform_per_digit() {
        // Owen scrambling keeps the first digit stratified: over one full period of base b,
        // each of the b intervals [k/b, (k+1)/b) holds exactly one point.
        for &base in &[3u32, 7] {
            let mut hits = vec![0; base as usize];
            for a in 0..base {
                let x = radical_inverse(base, a, true, 0x1234);
                hits[(x * base as f32) as usize] += 1;
            }
            assert!(hits.iter().all(|&h| h == 1), "base {base}: {hits:?}");
        }
    }
}
