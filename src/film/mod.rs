//! Images as estimates: the per-pixel accumulator the GPU fills (`accum_pixel`) and the film
//! made from it, per-pixel mean and variance of the mean. The lowest layer of the library: the
//! renderer, files, display transform, metrics and statistics all speak in films.

mod accum_pixel;

pub use accum_pixel::AccumPixel;

/// Linear RGB image estimate, row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel that went into every pixel.
    pub spp: u64,
    /// Per-pixel mean radiance.
    pub mean: Vec<[f32; 3]>,
    /// Per-pixel variance of the mean: sample variance / spp (0 when spp < 2).
    pub variance: Vec<[f32; 3]>,
}

impl Film {
    /// Mean and variance of the mean from compensated sums (computed in f64).
    pub fn from_accumulators(width: u32, height: u32, spp: u64, pixels: &[AccumPixel]) -> Film {
        Film::from_sums(width, height, spp, pixels.iter().map(AccumPixel::exact_sums))
    }

    /// Mean and variance of the mean from per-pixel (sum, sum of squares) of `spp` samples.
    pub fn from_sums(width: u32, height: u32, spp: u64, sums: impl ExactSizeIterator<Item = ([f64; 3], [f64; 3])>) -> Film {
        let n = spp as f64;
        let mut mean = Vec::with_capacity(sums.len());
        let mut variance = Vec::with_capacity(sums.len());
        for (sum, sum_sq) in sums {
            let mut m = [0.0f32; 3];
            let mut v = [0.0f32; 3];
            for c in 0..3 {
                let (sum, sum_sq) = (sum[c], sum_sq[c]);
                let mu = if n > 0.0 { sum / n } else { 0.0 };
                m[c] = mu as f32;
                if n > 1.0 {
                    // Unbiased sample variance, divided by n for the variance of the mean.
                    let s2 = ((sum_sq - n * mu * mu) / (n - 1.0)).max(0.0);
                    v[c] = (s2 / n) as f32;
                }
            }
            mean.push(m);
            variance.push(v);
        }
        Film { width, height, spp, mean, variance }
    }

    /// Averages `factor` x `factor` blocks of pixels (width and height must be multiples):
    /// block means, and variances of the block means (sum of variances / factor^4).
    pub fn downsample(&self, factor: u32) -> Film {
        assert!(factor > 0 && self.width % factor == 0 && self.height % factor == 0, "downsample: size not a multiple of {factor}");
        let (w, h) = (self.width / factor, self.height / factor);
        let n = (factor * factor) as f64;
        let mut mean = vec![[0.0f32; 3]; (w * h) as usize];
        let mut variance = vec![[0.0f32; 3]; (w * h) as usize];
        for by in 0..h {
            for bx in 0..w {
                let (mut m, mut v) = ([0.0f64; 3], [0.0f64; 3]);
                for y in by * factor..(by + 1) * factor {
                    for x in bx * factor..(bx + 1) * factor {
                        let i = (y * self.width + x) as usize;
                        for c in 0..3 {
                            m[c] += self.mean[i][c] as f64;
                            v[c] += self.variance[i][c] as f64;
                        }
                    }
                }
                let o = (by * w + bx) as usize;
                mean[o] = m.map(|x| (x / n) as f32);
                variance[o] = v.map(|x| (x / (n * n)) as f32);
            }
        }
        Film { width: w, height: h, spp: self.spp, mean, variance }
    }

    /// The average of independent renders of the same size (e.g. several seeds): mean of the
    /// means, variance of that mean = sum of variances / K^2; `spp` is the total.
    pub fn mean_of(films: &[Film]) -> Film {
        assert!(!films.is_empty(), "mean_of: no films");
        let k = films.len() as f64;
        let n = films[0].mean.len();
        let (mut mean, mut variance) = (vec![[0.0f32; 3]; n], vec![[0.0f32; 3]; n]);
        for i in 0..n {
            for c in 0..3 {
                mean[i][c] = (films.iter().map(|f| f.mean[i][c] as f64).sum::<f64>() / k) as f32;
                variance[i][c] = (films.iter().map(|f| f.variance[i][c] as f64).sum::<f64>() / (k * k)) as f32;
            }
        }
        Film { width: films[0].width, height: films[0].height, spp: films.iter().map(|f| f.spp).sum(), mean, variance }
    }

    /// Mean over all pixels and channels.
    pub fn average(&self) -> f64 {
        let total: f64 = self.mean.iter().flat_map(|p| p.iter()).map(|&x| x as f64).sum();
        total / (3 * self.mean.len()).max(1) as f64
    }

    /// True when every mean and variance is finite.
    pub fn is_finite(&self) -> bool {
        self.mean.iter().chain(&self.variance).flatten().all(|x| x.is_finite())
    }
}
