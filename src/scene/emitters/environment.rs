//! The environment: radiance from every direction at infinity (`shaders/emitters/environment.wgsl`),
//! constant (Mitsuba's `constant` emitter, `render.environment`) or from a latitude-longitude
//! image (Mitsuba's `envmap`, `EnvironmentMap`). Next event estimation
//! samples it only where the method asks (`Method::environment`); otherwise escaped rays
//! alone find it, as before it was a light.

use std::f64::consts::PI;

use glam::DVec3;

use super::{luminance, Light};
use crate::scene::Scene;

/// The environment, where it is not black.
pub(super) fn lights(scene: &Scene) -> Vec<Light> {
    if scene.has_environment() { vec![Light::Environment] } else { Vec::new() }
}

/// Emitted power of a constant environment seen by a scene of bounding radius r, as pbrt-v4's
/// UniformInfiniteLight::Phi: 4 pi (over directions) times pi r^2 (the scene's cross-section)
/// times the radiance.
pub(super) fn power(scene: &Scene) -> f64 {
    let r = bounding_radius(scene);
    let radiance = match &scene.environment_map {
        Some(map) => map.mean_luminance(),
        None => luminance(scene.render.environment),
    };
    4.0 * PI * PI * r * r * radiance
}

/// Radius of a sphere around the scene's bounded objects (spheres, mesh vertices, quadrics) and its
/// camera, centred on their bounding box; planes are unbounded and left out.
pub(super) fn bounding_radius(scene: &Scene) -> f64 {
    let mut lo = scene.camera.position;
    let mut hi = scene.camera.position;
    for o in scene.camera.ray_origin_corners(scene.render.width, scene.render.height) {
        lo = lo.min(o);
        hi = hi.max(o);
    }
    for s in &scene.spheres {
        lo = lo.min(s.center - DVec3::splat(s.radius));
        hi = hi.max(s.center + DVec3::splat(s.radius));
    }
    for v in scene.meshes.iter().flat_map(|m| m.positions.iter()) {
        lo = lo.min(*v);
        hi = hi.max(*v);
    }
    for v in scene.quadrics.iter().flat_map(|q| q.box_corners()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    (0.5 * (hi - lo).length()).max(1e-3)
}

/// Mitsuba's `envmap`: radiance from every direction at infinity, looked up in a
/// latitude-longitude image (`shaders/emitters/environment.wgsl`, `environment_map_radiance`).
/// A world direction d is turned into the map's frame by the inverse of `to_world` (a
/// rotation), v = R^T d; then u = atan2(v.x, -v.z) / 2 pi (wrapped into [0, 1)) and
/// t = acos(v.y) / pi, the image's top row looking along +y. As Mitsuba 3.9.1's RGB variants
/// (envmap.cpp `eval_spectrum`), the lookup is bilinear with texel centres at
/// x = u W - 1/2 (periodic in u) and rows at y = t (H - 1) (the first and last rows on the
/// poles), times `scale`.
#[derive(Debug, Clone)]
pub struct EnvironmentMap {
    /// The image file as found.
    pub file: std::path::PathBuf,
    pub image: std::sync::Arc<crate::scene::image_file::Image>,
    pub content_hash: String,
    pub scale: f64,
    /// The map's frame in the world: a rotation, rows of the matrix (local to world).
    pub to_world: [[f64; 3]; 3],
}

impl PartialEq for EnvironmentMap {
    fn eq(&self, o: &EnvironmentMap) -> bool {
        self.file == o.file && self.content_hash == o.content_hash && self.scale == o.scale && self.to_world == o.to_world
    }
}

/// Numbers of the map's record before its texels (`ENVIRONMENT_MAP_HEADER` in WGSL).
pub const ENVIRONMENT_MAP_HEADER: usize = 14;

/// Which of the map's two sampling distributions (`EnvSampling`'s importance-sampled
/// strategies), each packed as one table of the record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EnvDistribution {
    /// In proportion to the luminance times sin(theta).
    Luminance,
    /// MIS compensation (Karlík et al. 2019; pbrt-v4's `compensatedDistribution`): the
    /// luminance less its mean over the sphere, clamped at zero, times sin(theta). Zero where the
    /// map is at most its mean: complete only together with BSDF sampling under MIS.
    Compensated,
}

impl EnvironmentMap {
    /// Its record for the kernel (`environment_map` in environment.wgsl): width W, height H,
    /// scale, the world-to-map rotation R^T (9, rows), whether it can be importance-sampled
    /// by luminance (1: some texel is bright) and by the compensated distribution (1: some
    /// texel is brighter than the mean); then the texels' linear RGB (3 W H, rows from the top);
    /// then one table per `EnvDistribution` (luminance, compensated), each the density over uv
    /// per cell (W H, `sampling_tables`), the cumulative distribution over rows (H + 1) and
    /// each row's over its cells (H (W + 1)); zeros where that distribution is empty.
    pub fn pack(&self) -> Vec<f32> {
        let m = self.to_world;
        let mut data = vec![self.image.width as f32, self.image.height as f32, self.scale as f32];
        for c in 0..3 {
            for r in 0..3 {
                data.push(m[r][c] as f32);
            }
        }
        let tables = [EnvDistribution::Luminance, EnvDistribution::Compensated].map(|d| self.sampling_tables(d));
        data.extend(tables.iter().map(|(density, _, _)| if density.is_empty() { 0.0 } else { 1.0 }));
        debug_assert_eq!(data.len(), ENVIRONMENT_MAP_HEADER);
        for y in 0..self.image.height {
            for x in 0..self.image.width {
                data.extend(self.image.texel(x, y));
            }
        }
        let (w, h) = (self.image.width as usize, self.image.height as usize);
        for (density, rows, columns) in &tables {
            if density.is_empty() {
                data.extend(std::iter::repeat_n(0.0, w * h + h + 1 + h * (w + 1)));
            } else {
                data.extend(density.iter().map(|&d| d as f32));
                data.extend(rows.iter().map(|&c| c as f32));
                data.extend(columns.iter().map(|&c| c as f32));
            }
        }
        data
    }

    /// The weight of cell (x, y) of the uv square (u in [x/W, (x+1)/W), t in [y/H, (y+1)/H)) for
    /// luminance sampling: the largest luminance among the texels the bilinear lookup reads
    /// anywhere in the cell (columns x-1..x+1, the rows around it), times sin(theta) at its
    /// centre. Never zero where the radiance is not, so sampling by it is unbiased.
    fn cell_weight(&self, x: u32, y: u32) -> f64 {
        let h = self.image.height as i32;
        let rows = |t: f64| t * (h - 1) as f64;
        let (r0, r1) = (rows(y as f64 / h as f64).floor() as i32, (rows((y + 1) as f64 / h as f64).ceil() as i32).min(h - 1));
        let mut max: f64 = 0.0;
        for r in r0..=r1 {
            for c in (x as i32 - 1)..=(x as i32 + 1) {
                max = max.max(luminance(DVec3::from(self.texel(c, r).map(f64::from))));
            }
        }
        max * (PI * (y as f64 + 0.5) / h as f64).sin()
    }

    /// The cell weights of `distribution`, rows from the top. Compensated: each cell's
    /// luminance bound less their mean over the sphere (the bounds weighted by sin(theta), the
    /// solid angle of their rows), clamped at zero, then times sin(theta); where no cell
    /// exceeds the mean (a constant map) every cell keeps its sin(theta), uniform over the
    /// sphere, as pbrt-v4 falls back to a uniform distribution.
    fn cell_weights(&self, distribution: EnvDistribution) -> Vec<f64> {
        let (w, h) = (self.image.width, self.image.height);
        let sin_theta = |y: u32| (PI * (y as f64 + 0.5) / h as f64).sin();
        let luminance: Vec<f64> = (0..h).flat_map(|y| (0..w).map(move |x| (x, y))).map(|(x, y)| self.cell_weight(x, y)).collect();
        match distribution {
            EnvDistribution::Luminance => luminance,
            EnvDistribution::Compensated => {
                // The bounds themselves: luminance / sin(theta), the mean by solid angle.
                let (mut sum, mut solid_angle) = (0.0, 0.0);
                for y in 0..h {
                    let s = sin_theta(y);
                    for x in 0..w {
                        sum += luminance[(y * w + x) as usize];
                        solid_angle += s;
                    }
                }
                let mean = sum / solid_angle;
                let compensated: Vec<f64> = (0..h)
                    .flat_map(|y| (0..w).map(move |x| (x, y)))
                    .map(|(x, y)| {
                        let s = sin_theta(y);
                        (luminance[(y * w + x) as usize] / s - mean).max(0.0) * s
                    })
                    .collect();
                if compensated.iter().any(|&c| c > 0.0) || !(sum > 0.0) {
                    compensated
                } else {
                    (0..h).flat_map(|y| (0..w).map(move |_| sin_theta(y))).collect()
                }
            }
        }
    }

    /// A sampling distribution: the density over the uv square per cell (mean 1), the
    /// cumulative distribution over rows and each row's over its cells; empty when every
    /// weight is zero (a black map: uniform sampling then).
    pub fn sampling_tables(&self, distribution: EnvDistribution) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let (w, h) = (self.image.width, self.image.height);
        let weights = self.cell_weights(distribution);
        let total: f64 = weights.iter().sum();
        if !(total > 0.0) {
            return (Vec::new(), Vec::new(), Vec::new());
        }
        let mean = total / (w * h) as f64;
        let density = weights.iter().map(|x| x / mean).collect();
        let mut rows = vec![0.0];
        let mut columns = Vec::with_capacity((h * (w + 1)) as usize);
        for y in 0..h as usize {
            let row = &weights[y * w as usize..(y + 1) * w as usize];
            let sum: f64 = row.iter().sum();
            rows.push(rows[y] + sum / total);
            columns.push(0.0);
            let mut acc = 0.0;
            for (x, v) in row.iter().enumerate() {
                acc += v;
                // A black row is never drawn: its cells' distribution is uniform.
                columns.push(if sum > 0.0 { acc / sum } else { (x + 1) as f64 / w as f64 });
            }
            *columns.last_mut().expect("a row has cells") = 1.0;
        }
        *rows.last_mut().expect("a map has rows") = 1.0;
        (density, rows, columns)
    }

    /// Texel (x, y) with x periodic and y clamped.
    fn texel(&self, x: i32, y: i32) -> [f32; 3] {
        let (w, h) = (self.image.width as i32, self.image.height as i32);
        self.image.texel(x.rem_euclid(w) as u32, y.clamp(0, h - 1) as u32)
    }

    /// The radiance arriving from world direction `d` (unit), in f32 as the kernel computes it:
    /// the host's twin of `environment_map_radiance`.
    pub fn radiance(&self, d: [f32; 3]) -> [f32; 3] {
        let m = self.to_world.map(|r| r.map(|x| x as f32));
        // v = R^T d: the columns of R dotted with d.
        let v: [f32; 3] = std::array::from_fn(|c| m[0][c] * d[0] + m[1][c] * d[1] + m[2][c] * d[2]);
        let u = v[0].atan2(-v[2]) * (0.5 / std::f32::consts::PI);
        let u = u - u.floor();
        let t = (v[1].clamp(-1.0, 1.0).acos() * std::f32::consts::FRAC_1_PI).clamp(0.0, 1.0);
        let (w, h) = (self.image.width as f32, self.image.height as f32);
        let (px, py) = (u * w - 0.5, t * (h - 1.0));
        let (x0, y0) = (px.floor(), py.floor());
        let (fx, fy) = (px - x0, py - y0);
        let (x0, y0) = (x0 as i32, y0 as i32);
        let (t00, t10, t01, t11) = (self.texel(x0, y0), self.texel(x0 + 1, y0), self.texel(x0, y0 + 1), self.texel(x0 + 1, y0 + 1));
        let scale = self.scale as f32;
        std::array::from_fn(|c| {
            let top = t00[c] + fx * (t10[c] - t00[c]);
            let bottom = t01[c] + fx * (t11[c] - t01[c]);
            (top + fy * (bottom - top)) * scale
        })
    }

    /// No radiance from any direction (scale 0, or every texel black).
    pub fn is_black(&self) -> bool {
        self.scale == 0.0 || (0..self.image.height).all(|y| (0..self.image.width).all(|x| self.image.texel(x, y).iter().all(|c| *c == 0.0)))
    }

    /// Its mean radiance over the sphere of directions (the texels weighted by the solid angle
    /// of their rows, sin theta), in luminance: what power-proportional light selection weighs.
    pub fn mean_luminance(&self) -> f64 {
        let (w, h) = (self.image.width, self.image.height);
        let (mut sum, mut weight) = (0.0, 0.0);
        for y in 0..h {
            let theta = if h > 1 { PI * y as f64 / (h - 1) as f64 } else { 0.5 * PI };
            let s = theta.sin().max(1e-3);
            for x in 0..w {
                sum += s * luminance(DVec3::from(self.image.texel(x, y).map(f64::from)));
                weight += s;
            }
        }
        self.scale * sum / weight.max(1e-12)
    }
}
