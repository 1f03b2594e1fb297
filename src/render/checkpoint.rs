//! Checkpoints of a render in progress: the raw per-pixel accumulators (Kahan-compensated sums
//! and sums of squares as float32, sample count and 64-bit ray count as uint32 channels) in an
//! OpenEXR file, with what produced them in the header. Restoring them into a `Renderer` and
//! continuing gives a result bit-identical to a render that never stopped, because every sample
//! is a pure function of (pixel, sample index, dimension, seed) and the accumulators are stored
//! exactly.
//!
//! Channels: `sum.{R,G,B}`, `sum_err.*`, `sum_sq.*`, `sum_sq_err.*` (f32), `count`, `rays_lo`,
//! `rays_hi` (u32), and `faults` (u32: samples a researcher's technique faulted in) where the
//! method uses a technique. Header: `pathlab:kind = accumulator`, `scene_hash`, `sampler`, `bsdf`,
//! `scene_hash_encoding`, `data_sha256` (see `output::content_sha256`), `lights`, `seed`, `max_depth`, `first_sample`, `spp`, `render_seconds`
//! (all sessions),
//! `version`. Written through a temporary file and renamed, so a checkpoint on disk is always
//! complete: a `kill -9` loses at most the samples since the last one.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use bytemuck::Zeroable;
use exr::prelude::*;
use std::result::Result;

use crate::film::AccumPixel;
use crate::method::Method;
use crate::output::attributes::AttributeError;
use crate::output::{read_exr_layer, write_exr_layer, Metadata, OutputError, CHECKSUM_KEY};
use crate::scene::hash::SCENE_HASH_ENCODING;

use super::{Budget, Progress, RenderError, RenderStats, Renderer, MAX_SPP};
use crate::film::Film;

/// What must match for a checkpoint to be continued: scene content, method, seed, size, depth.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CheckpointKey {
    /// `Scene::content_hash` of the scene as rendered (size and depth overrides applied).
    pub scene_hash: String,
    pub method: Method,
    pub seed: u32,
    pub width: u32,
    pub height: u32,
    pub max_depth: u32,
    /// Russian roulette's first vertex (`render.rr_depth`), if any.
    pub rr_depth: Option<u32>,
    /// The researchers' techniques of the method, with their files' hashes
    /// (`scene::technique::stamp`): a file edited since does not continue.
    pub techniques: String,
}

/// Saved accumulators of a render.
#[derive(Debug, Clone)]
pub struct Checkpoint {
    pub key: CheckpointKey,
    /// Sample index of the first sample accumulated.
    pub first_sample: u64,
    /// Samples per pixel accumulated.
    pub spp: u64,
    /// Wall time spent rendering them, over every session.
    pub render_seconds: f64,
    /// For a shard (`render --shard I/N`): the whole range [0, total) its render is split from,
    /// so that `merge` can name missing shards at the end too.
    pub planned_total: Option<u64>,
    pub pixels: Vec<AccumPixel>,
}

#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    #[error(transparent)]
    Output(#[from] OutputError),
    #[error(transparent)]
    Render(#[from] RenderError),
    #[error("{}: not a pathlab accumulator file: {message}", path.display())]
    Invalid { path: PathBuf, message: String },
    #[error("{}: made by another render ({field} is {found}, this render has {expected}); remove it or choose another file", path.display())]
    Mismatch { path: PathBuf, field: &'static str, found: String, expected: String },
}

const F32_CHANNELS: [&str; 4] = ["sum", "sum_err", "sum_sq", "sum_sq_err"];
const RGB: [&str; 3] = ["R", "G", "B"];

/// The `pathlab:rr_depth` attribute: the first roulette vertex, or `off`.
pub fn rr_depth_attr(rr_depth: Option<u32>) -> String {
    rr_depth.map_or("off".to_string(), |k| k.to_string())
}

impl CheckpointKey {
    fn fields(&self) -> Vec<(&'static str, String)> {
        // Size and depth before the scene hash, which covers them too: a mismatch names the
        // most specific field.
        vec![
            ("width", self.width.to_string()),
            ("height", self.height.to_string()),
            ("max_depth", self.max_depth.to_string()),
            ("rr_depth", rr_depth_attr(self.rr_depth)),
            ("sampler", self.method.sampler.to_string()),
            ("bsdf", self.method.bsdf.to_string()),
            ("lights", self.method.lights.to_string()),
            // `default`: the scene's (Scene::default_light_select).
            ("light_select", self.method.select.map_or("default".to_string(), |s| s.to_string())),
            ("triangle_sampling", self.method.triangles.to_string()),
            ("microfacet_sampling", self.method.microfacet.to_string()),
            ("lobe_selection", self.method.lobes.to_string()),
            ("environment_sampling", if self.method.environment { "on" } else { "off" }.to_string()),
            ("environment_map_sampling", self.method.env_sampling.to_string()),
            ("techniques", if self.techniques.is_empty() { "none".to_string() } else { self.techniques.clone() }),
            ("seed", self.seed.to_string()),
            ("scene_hash", self.scene_hash.clone()),
        ]
    }

    /// The first field where `other` differs: (field, other's value, this one's value).
    pub fn first_difference(&self, other: &CheckpointKey) -> Option<(&'static str, String, String)> {
        self.fields().into_iter().zip(other.fields()).find(|((_, a), (_, b))| a != b).map(|((field, a), (_, b))| (field, b, a))
    }

    /// An error naming the first field where `other` (read from `path`) differs.
    fn check(&self, other: &CheckpointKey, path: &Path) -> Result<(), CheckpointError> {
        match self.first_difference(other) {
            Some((field, found, expected)) => Err(CheckpointError::Mismatch { path: path.to_path_buf(), field, found, expected }),
            None => Ok(()),
        }
    }
}

impl Checkpoint {
    /// The film these accumulators hold.
    pub fn film(&self) -> Film {
        Film::from_accumulators(self.key.width, self.key.height, self.spp, &self.pixels)
    }

    /// Rays traced for them.
    pub fn rays(&self) -> u64 {
        self.pixels.iter().map(AccumPixel::rays).sum()
    }

    /// Samples in which a researcher's technique faulted (stored, as channel `faults`, where the
    /// method uses a technique).
    pub fn faults(&self) -> u64 {
        self.pixels.iter().map(|p| p.faults as u64).sum()
    }

    /// Writes the checkpoint atomically.
    pub fn write(&self, path: &Path) -> Result<(), OutputError> {
        let mut list = Vec::new();
        for name in F32_CHANNELS {
            for (c, rgb) in RGB.iter().enumerate() {
                let values: Vec<f32> = self
                    .pixels
                    .iter()
                    .map(|p| match name {
                        "sum" => p.sum[c],
                        "sum_err" => p.sum_err[c],
                        "sum_sq" => p.sum_sq[c],
                        _ => p.sum_sq_err[c],
                    })
                    .collect();
                list.push(AnyChannel::new(format!("{name}.{rgb}").as_str(), FlatSamples::F32(values)));
            }
        }
        list.push(AnyChannel::new("count", FlatSamples::U32(self.pixels.iter().map(|p| p.count).collect())));
        list.push(AnyChannel::new("rays_lo", FlatSamples::U32(self.pixels.iter().map(|p| p.rays_lo).collect())));
        list.push(AnyChannel::new("rays_hi", FlatSamples::U32(self.pixels.iter().map(|p| p.rays_hi).collect())));
        if !self.key.techniques.is_empty() {
            list.push(AnyChannel::new("faults", FlatSamples::U32(self.pixels.iter().map(|p| p.faults).collect())));
        }
        let mut header = self.key.fields();
        header.extend([
            ("kind", "accumulator".to_string()),
            ("scene_hash_encoding", SCENE_HASH_ENCODING.to_string()),
            ("first_sample", self.first_sample.to_string()),
            ("spp", self.spp.to_string()),
            ("render_seconds", format!("{:.6}", self.render_seconds)),
            ("version", crate::VERSION.to_string()),
        ]);
        if let Some(total) = self.planned_total {
            header.push(("planned_total", total.to_string()));
        }
        let metadata: Metadata = header.into_iter().map(|(k, v)| (k.to_string(), v)).collect();
        write_exr_layer(path, (self.key.width as usize, self.key.height as usize), list, &metadata)
    }

    /// Reads a checkpoint, checking that it is complete, consistent and intact: every header
    /// number parsed as what it is and range-checked, the sample range within 2^32, every sum
    /// finite and non-negative (radiance is), sums of squares consistent with the sums, every
    /// pixel's count equal to the header's spp, and the data's SHA-256 equal to the header's.
    pub fn read(path: &Path) -> Result<Checkpoint, CheckpointError> {
        let invalid = |message: String| CheckpointError::Invalid { path: path.to_path_buf(), message };
        let (layer, header) = read_exr_layer(path).map_err(|e| match e {
            OutputError::Attribute(a) => invalid(a.message),
            OutputError::NotExr { message, .. } => invalid(format!("cannot read it as OpenEXR ({message})")),
            OutputError::Read { message, .. } => invalid(message),
            other => invalid(other.to_string()),
        })?;
        let attr = |e: AttributeError| invalid(e.message);
        let (w, h) = (layer.size.width(), layer.size.height());
        if header.text("kind").map_err(attr)? != "accumulator" {
            return Err(invalid("pathlab:kind is not `accumulator`".into()));
        }
        // Files made before the scene hash had a stable encoding carry a hash of the scene's
        // debug text, which no later version can reproduce or compare.
        match header.get("scene_hash_encoding") {
            Some(v) if v == SCENE_HASH_ENCODING.to_string() => {}
            Some(v) => return Err(invalid(format!("its scene hash uses encoding {v}; this pathlab knows encoding {SCENE_HASH_ENCODING}"))),
            None => {
                return Err(invalid(format!(
                    "it was made by pathlab {} (before 0.2.0), whose scene hash is not stable across versions, so the scene it \
                     belongs to cannot be checked; render it again, or merge/resume it with the version that made it",
                    header.get("version").unwrap_or("?")
                )))
            }
        }
        let u32_max = u32::MAX as u64;
        // Files written before triangle meshes have neither light option: the defaults.
        let select = match header.get("light_select") {
            None | Some("default") => None,
            Some(v) => Some(v.parse().map_err(|e| invalid(format!("pathlab:light_select: {e}")))?),
        };
        let triangles = match header.get("triangle_sampling") {
            None => crate::method::TriangleSampling::Area,
            Some(v) => v.parse().map_err(|e| invalid(format!("pathlab:triangle_sampling: {e}")))?,
        };
        // Files written before microfacets have Mitsuba's default, visible normals.
        let microfacet = match header.get("microfacet_sampling") {
            None => crate::method::MicrofacetSampling::Vndf,
            Some(v) => v.parse().map_err(|e| invalid(format!("pathlab:microfacet_sampling: {e}")))?,
        };
        // Files written before environment maps have Mitsuba's luminance sampling.
        let env_sampling = match header.get("environment_map_sampling") {
            None => crate::method::EnvSampling::Luminance,
            Some(v) => v.parse().map_err(|e| invalid(format!("pathlab:environment_map_sampling: {e}")))?,
        };
        // Files written before layered BSDFs have Mitsuba's Fresnel-weighted lobe selection.
        let lobes = match header.get("lobe_selection") {
            None => crate::method::LobeSelection::Fresnel,
            Some(v) => v.parse().map_err(|e| invalid(format!("pathlab:lobe_selection: {e}")))?,
        };
        // Files written before the environment was a light never sampled it.
        let environment = match header.get("environment_sampling") {
            None | Some("off") => false,
            Some("on") => true,
            Some(v) => return Err(invalid(format!("pathlab:environment_sampling is `{v}`, not `on` or `off`"))),
        };
        let method = Method {
            sampler: header.text("sampler").map_err(attr)?.parse().map_err(|e| invalid(format!("pathlab:sampler: {e}")))?,
            bsdf: header.text("bsdf").map_err(attr)?.parse().map_err(|e| invalid(format!("pathlab:bsdf: {e}")))?,
            lights: header.text("lights").map_err(attr)?.parse().map_err(|e| invalid(format!("pathlab:lights: {e}")))?,
            select,
            triangles,
            microfacet,
            lobes,
            environment,
            env_sampling,
            bsdf_technique: None,
            light_technique: None,
            env_technique: None,
        };
        // Files written before researchers' techniques use none.
        let techniques = match header.get("techniques") {
            None | Some("none") => String::new(),
            Some(v) => v.to_string(),
        };
        let method = crate::scene::technique::method_from_stamp(method, &techniques).map_err(|e| invalid(format!("pathlab:techniques: {e}")))?;
        let scene_hash = header.text("scene_hash").map_err(attr)?.to_string();
        if scene_hash.len() != 16 || !scene_hash.bytes().all(|b| b.is_ascii_hexdigit() && !b.is_ascii_uppercase()) {
            return Err(invalid(format!("pathlab:scene_hash is `{scene_hash}`, not 16 hex digits")));
        }
        let key = CheckpointKey {
            scene_hash,
            method,
            seed: header.whole("seed", u32_max).map_err(attr)? as u32,
            width: header.whole("width", u32_max).map_err(attr)? as u32,
            height: header.whole("height", u32_max).map_err(attr)? as u32,
            max_depth: header.whole("max_depth", u32_max).map_err(attr)? as u32,
            // Files written before Russian roulette have none.
            rr_depth: match header.get("rr_depth") {
                None | Some("off") => None,
                Some(v) => Some(v.parse::<u32>().ok().filter(|&k| k >= 1).ok_or_else(|| invalid(format!("pathlab:rr_depth is `{v}`, not a depth >= 1 or `off`")))?),
            },
            techniques,
        };
        if (key.width as usize, key.height as usize) != (w, h) {
            return Err(invalid(format!("header says {}x{}, the data is {w}x{h}", key.width, key.height)));
        }
        // Sample indices are u32: a range ends at 2^32 at the latest.
        let first_sample = header.whole("first_sample", MAX_SPP - 1).map_err(attr)?;
        let spp = header.whole("spp", MAX_SPP).map_err(attr)?;
        if first_sample + spp > MAX_SPP {
            return Err(invalid(format!("samples {first_sample}..{} go beyond 2^32, where sample indices end", first_sample + spp)));
        }
        let planned_total = header.whole_opt("planned_total", MAX_SPP).map_err(attr)?;
        let render_seconds = header.real("render_seconds", 0.0).map_err(attr)?;
        let expected: Vec<String> = F32_CHANNELS
            .iter()
            .flat_map(|n| RGB.iter().map(move |c| format!("{n}.{c}")))
            .chain(["count", "rays_lo", "rays_hi", "faults"].map(String::from))
            .collect();
        if let Some(extra) = layer.channel_data.list.iter().find(|c| !expected.iter().any(|e| c.name == Text::from(e.as_str()))) {
            return Err(invalid(format!("unexpected channel {}", extra.name)));
        }
        let channel = |name: &str| layer.channel_data.list.iter().find(|c| c.name == Text::from(name));
        let f32s = |name: &str| -> Result<Vec<f32>, CheckpointError> {
            match channel(name).map(|c| &c.sample_data) {
                Some(FlatSamples::F32(v)) if v.len() == w * h => Ok(v.clone()),
                _ => Err(invalid(format!("channel {name} missing or not float32"))),
            }
        };
        let u32s = |name: &str| -> Result<Vec<u32>, CheckpointError> {
            match channel(name).map(|c| &c.sample_data) {
                Some(FlatSamples::U32(v)) if v.len() == w * h => Ok(v.clone()),
                _ => Err(invalid(format!("channel {name} missing or not uint32"))),
            }
        };
        let mut pixels = vec![AccumPixel::zeroed(); w * h];
        for name in F32_CHANNELS {
            for (c, rgb) in RGB.iter().enumerate() {
                for (p, v) in pixels.iter_mut().zip(f32s(&format!("{name}.{rgb}"))?) {
                    match name {
                        "sum" => p.sum[c] = v,
                        "sum_err" => p.sum_err[c] = v,
                        "sum_sq" => p.sum_sq[c] = v,
                        _ => p.sum_sq_err[c] = v,
                    }
                }
            }
        }
        for (p, ((count, lo), hi)) in pixels.iter_mut().zip(u32s("count")?.into_iter().zip(u32s("rays_lo")?).zip(u32s("rays_hi")?)) {
            (p.count, p.rays_lo, p.rays_hi) = (count, lo, hi);
        }
        // Faulted samples of a researcher's technique: only files of a method that uses one.
        if channel("faults").is_some() {
            for (p, faults) in pixels.iter_mut().zip(u32s("faults")?) {
                p.faults = faults;
            }
        }
        let at = |i: usize| format!("pixel ({}, {})", i % w.max(1), i / w.max(1));
        if let Some(i) = AccumPixel::first_miscounted(&pixels, spp) {
            return Err(invalid(format!("{} holds {} samples, the header says {spp}", at(i), pixels[i].count)));
        }
        for (i, p) in pixels.iter().enumerate() {
            if let Some(problem) = accumulator_problem(p, spp) {
                return Err(invalid(format!("{}: {problem}", at(i))));
            }
        }
        // read_exr_layer verified the checksum of a file that has one; every 0.2 file has one.
        if header.get(CHECKSUM_KEY).is_none() {
            return Err(invalid(format!("header attribute pathlab:{CHECKSUM_KEY} missing (every pathlab 0.2 accumulator file has one)")));
        }
        Ok(Checkpoint { key, first_sample, spp, render_seconds, planned_total, pixels })
    }
}

/// What is impossible about one pixel's accumulator of `spp` non-negative radiance samples:
/// a non-finite value, a negative sum or sum of squares, or a sum of squares below what the sum
/// implies (sum^2 / n, Cauchy-Schwarz; the variance would be negative).
fn accumulator_problem(p: &AccumPixel, spp: u64) -> Option<String> {
    const RGB: [&str; 3] = ["R", "G", "B"];
    let (sum, sum_sq) = p.exact_sums();
    for c in 0..3 {
        let values = [("sum", p.sum[c]), ("sum_err", p.sum_err[c]), ("sum_sq", p.sum_sq[c]), ("sum_sq_err", p.sum_sq_err[c])];
        if let Some((name, v)) = values.iter().find(|(_, v)| !v.is_finite()) {
            return Some(format!("{name}.{} is {v}", RGB[c]));
        }
        if sum[c] < 0.0 || sum_sq[c] < 0.0 {
            return Some(format!("a negative sum ({} = {:e}, sum_sq.{} = {:e}): radiance samples are not negative", RGB[c], sum[c], RGB[c], sum_sq[c]));
        }
        // n sum_sq >= sum^2, with room for the rounding of f32 compensated sums.
        let n = spp as f64;
        if n > 0.0 && n * sum_sq[c] < sum[c] * sum[c] * (1.0 - 1e-4) - 1e-30 {
            return Some(format!("sum_sq.{} = {:e} is below sum^2 / spp = {:e}: a negative variance", RGB[c], sum_sq[c], sum[c] * sum[c] / n));
        }
    }
    None
}

/// What to do with an accumulator file that already exists when a render starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Resume {
    /// Start afresh; the file is replaced at the first save.
    Never,
    /// Continue it when present (the study's reference).
    IfPresent,
    /// Continue it; its absence is an error (`render --resume`).
    Required,
}

/// Where and how often a render saves its accumulators.
#[derive(Debug, Clone)]
pub struct CheckpointPlan {
    pub path: PathBuf,
    pub every: Duration,
    pub resume: Resume,
    /// Recorded in the file (see `Checkpoint::planned_total`).
    pub planned_total: Option<u64>,
}

impl CheckpointPlan {
    /// The saved accumulators this plan continues from, checked against `key`, a render
    /// starting at sample `first_sample` and at most `total_spp` samples: `None` when the plan
    /// starts afresh. Needs no GPU: `render --resume` calls it before opening one.
    pub fn saved(&self, key: &CheckpointKey, first_sample: u64, total_spp: u64) -> Result<Option<Checkpoint>, CheckpointError> {
        let path = self.path.as_path();
        let exists = path.exists();
        if self.resume == Resume::Required && !exists {
            return Err(CheckpointError::Invalid { path: path.to_path_buf(), message: "no such file to resume from".into() });
        }
        if !exists || self.resume == Resume::Never {
            return Ok(None);
        }
        let saved = Checkpoint::read(path)?;
        key.check(&saved.key, path)?;
        if saved.first_sample != first_sample || saved.spp > total_spp {
            return Err(CheckpointError::Mismatch {
                path: path.to_path_buf(),
                field: "samples",
                found: format!("{}..{}", saved.first_sample, saved.first_sample + saved.spp),
                expected: format!("a start at {first_sample} and at most {total_spp} spp"),
            });
        }
        Ok(Some(saved))
    }
}

/// Renders until the renderer holds `total_spp` samples per pixel (fresh, for `key`, its first
/// sample index already set), saving the accumulators to `plan.path` every `plan.every` and at
/// the end. A saved file of another key is refused naming the field. Returns the final
/// checkpoint (its `render_seconds` counts every session) and whether `cancel` stopped it.
pub fn render_checkpointed(
    renderer: &mut Renderer,
    key: &CheckpointKey,
    total_spp: u64,
    plan: &CheckpointPlan,
    cancel: &AtomicBool,
    mut progress: impl FnMut(Progress),
) -> Result<(Checkpoint, bool), CheckpointError> {
    let mut seconds_before = 0.0;
    if let Some(saved) = plan.saved(key, renderer.first_sample(), total_spp)? {
        renderer.restore(saved.first_sample, saved.spp, &saved.pixels)?;
        seconds_before = saved.render_seconds;
    }
    let path = plan.path.as_path();
    let start = Instant::now();
    let mut interrupted = false;
    loop {
        let remaining = total_spp - renderer.spp();
        if remaining > 0 && !interrupted {
            let stats: RenderStats =
                renderer.render_until(Budget::Samples(remaining), Some(Instant::now() + plan.every), cancel, &mut progress)?;
            interrupted = stats.interrupted;
        }
        let checkpoint = Checkpoint {
            key: key.clone(),
            first_sample: renderer.first_sample(),
            spp: renderer.spp(),
            render_seconds: seconds_before + start.elapsed().as_secs_f64(),
            planned_total: plan.planned_total,
            pixels: renderer.accumulators()?,
        };
        checkpoint.write(path)?;
        if interrupted || checkpoint.spp >= total_spp {
            return Ok((checkpoint, interrupted));
        }
    }
}
