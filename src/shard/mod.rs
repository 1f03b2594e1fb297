//! Renders split across machines: sample-index ranges, and the exact merge of their partial
//! files.
//!
//! A part is an accumulator file (`render::Checkpoint`): the raw per-pixel sums of the samples
//! with indices [first_sample, first_sample + spp) of every pixel. Every sampler addresses its
//! samples by (pixel, sample index, dimension, seed), so parts rendered anywhere, in any order,
//! hold exactly the samples one long render would; merging adds their compensated sums in f64.
//! The merged image equals a single render of the same total range up to the rounding of the
//! summation order (tested: `tests/shard_merge.rs`).

use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::render::{Checkpoint, CheckpointError, CheckpointKey};
use crate::film::Film;

/// `START..END`: sample indices START (inclusive) to END (exclusive).
pub fn parse_range(s: &str) -> Result<Range<u64>, String> {
    let (a, b) = s.split_once("..").ok_or_else(|| format!("expected START..END, got `{s}`"))?;
    let parse = |v: &str| v.trim().parse::<u64>().map_err(|_| format!("`{v}` in `{s}` is not a sample index"));
    let (start, end) = (parse(a)?, parse(b)?);
    if end <= start {
        return Err(format!("the range `{s}` is empty: END must be greater than START"));
    }
    if end > crate::render::MAX_SPP {
        return Err(format!("sample indices end at 2^32 (the range `{s}` goes beyond)"));
    }
    Ok(start..end)
}

/// `I/N`: the I-th (0-based) of N shards.
pub fn parse_shard(s: &str) -> Result<(u64, u64), String> {
    let (i, n) = s.split_once('/').ok_or_else(|| format!("expected I/N, got `{s}`"))?;
    let parse = |v: &str| v.trim().parse::<u64>().map_err(|_| format!("`{v}` in `{s}` is not a whole number"));
    let (i, n) = (parse(i)?, parse(n)?);
    if n == 0 || i >= n {
        return Err(format!("shard `{s}`: need 0 <= I < N"));
    }
    Ok((i, n))
}

/// The I-th of N near-equal ranges of [0, total): [floor(total i / n), floor(total (i+1) / n)).
pub fn shard_range(i: u64, n: u64, total: u64) -> Range<u64> {
    let at = |k: u64| ((total as u128 * k as u128) / n as u128) as u64;
    at(i)..at(i + 1)
}

#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    #[error("no parts to merge")]
    NoParts,
    #[error(transparent)]
    Read(#[from] CheckpointError),
    #[error("{}: {field} is {found}, but {} has {expected}: parts of different renders cannot be merged", path.display(), first.display())]
    Mismatch { path: PathBuf, first: PathBuf, field: &'static str, found: String, expected: String },
    #[error("{} (samples {}..{}) overlaps {} (samples {}..{})", a.display(), ra.start, ra.end, b.display(), rb.start, rb.end)]
    Overlap { a: PathBuf, ra: Range<u64>, b: PathBuf, rb: Range<u64> },
    #[error("samples missing: {}; render them, or merge what is there with --allow-gaps", fmt_gaps(.0))]
    Gaps(Vec<Gap>),
}

/// Sample indices no part holds, and the parts around them (whose declared ranges leave it).
#[derive(Debug, Clone, PartialEq)]
pub struct Gap {
    pub range: Range<u64>,
    /// The part that ends where the gap starts, and the one that starts where it ends.
    pub after: Option<(PathBuf, Range<u64>)>,
    pub before: Option<(PathBuf, Range<u64>)>,
    /// At the end: the part whose planned total (`--shard`) the ranges fall short of.
    pub planned_by: Option<(PathBuf, u64)>,
}

impl std::fmt::Display for Gap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let part = |(p, r): &(PathBuf, Range<u64>)| format!("{} ({}..{})", p.display(), r.start, r.end);
        write!(f, "{}..{}", self.range.start, self.range.end)?;
        match (&self.after, &self.before) {
            (Some(a), Some(b)) => write!(f, " (between {} and {})", part(a), part(b))?,
            (None, Some(b)) => write!(f, " (before {})", part(b))?,
            (Some(a), None) => write!(f, " (after {})", part(a))?,
            (None, None) => {}
        }
        if let Some((p, total)) = &self.planned_by {
            write!(f, " of the {total} samples {} plans", p.display())?;
        }
        Ok(())
    }
}

fn fmt_gaps(gaps: &[Gap]) -> String {
    gaps.iter().map(Gap::to_string).collect::<Vec<_>>().join(", ")
}

/// What a merge produced.
#[derive(Debug, Clone)]
pub struct Merged {
    pub key: CheckpointKey,
    pub film: Film,
    /// Samples per pixel merged (the sum of the parts').
    pub spp: u64,
    pub rays: u64,
    /// Samples in which a researcher's technique faulted, over all parts.
    pub faults: u64,
    /// Rendering time of all parts together.
    pub render_seconds: f64,
    /// Sample ranges missing (only with `allow_gaps`).
    pub gaps: Vec<Gap>,
    /// The parts' ranges, in order.
    pub ranges: Vec<Range<u64>>,
}

/// Reads and merges `paths`: all from the same scene (content hash), method, seed, size and
/// depth; ranges neither overlapping nor leaving gaps in [0, end) (where end is the shards'
/// planned total, or the last range's end), unless `allow_gaps`.
pub fn merge(paths: &[PathBuf], allow_gaps: bool) -> Result<Merged, MergeError> {
    let first_path = paths.first().ok_or(MergeError::NoParts)?;
    let mut parts: Vec<(PathBuf, Checkpoint)> = Vec::new();
    for p in paths {
        parts.push((p.clone(), Checkpoint::read(p)?));
    }
    let key = parts[0].1.key.clone();
    for (path, part) in &parts[1..] {
        if let Some((field, found, expected)) = key.first_difference(&part.key) {
            return Err(MergeError::Mismatch { path: path.clone(), first: first_path.clone(), field, found, expected });
        }
    }
    parts.sort_by_key(|(_, c)| c.first_sample);
    let range = |c: &Checkpoint| c.first_sample..c.first_sample + c.spp;
    let mut gaps = Vec::new();
    let mut covered = 0u64;
    let named = |w: usize| (parts[w].0.clone(), range(&parts[w].1));
    for w in 0..parts.len() {
        let r = range(&parts[w].1);
        if w > 0 && r.start < range(&parts[w - 1].1).end {
            let (a, b) = (&parts[w - 1], &parts[w]);
            return Err(MergeError::Overlap { a: a.0.clone(), ra: range(&a.1), b: b.0.clone(), rb: r });
        }
        if r.start > covered {
            gaps.push(Gap { range: covered..r.start, after: (w > 0).then(|| named(w - 1)), before: Some(named(w)), planned_by: None });
        }
        covered = r.end;
    }
    // Part ranges are validated by `Checkpoint::read` (they end at 2^32 at the latest).
    if let Some((path, planned)) = parts.iter().filter_map(|(p, c)| c.planned_total.map(|t| (p, t))).max_by_key(|(_, t)| *t) {
        if planned > covered {
            gaps.push(Gap {
                range: covered..planned,
                after: Some(named(parts.len() - 1)),
                before: None,
                planned_by: Some((path.clone(), planned)),
            });
        }
    }
    if !gaps.is_empty() && !allow_gaps {
        return Err(MergeError::Gaps(gaps));
    }
    // Kahan's err holds minus the part not yet in `sum`: each part's exact sum is sum - err;
    // the parts' sums are added in f64.
    let n = parts[0].1.pixels.len();
    let mut sums = vec![([0.0f64; 3], [0.0f64; 3]); n];
    let mut rays = 0u64;
    let faults = parts.iter().map(|(_, c)| c.faults()).sum();
    for (_, part) in &parts {
        for (acc, p) in sums.iter_mut().zip(&part.pixels) {
            let (sum, sum_sq) = p.exact_sums();
            for c in 0..3 {
                acc.0[c] += sum[c];
                acc.1[c] += sum_sq[c];
            }
            rays += p.rays();
        }
    }
    let spp: u64 = parts.iter().map(|(_, c)| c.spp).sum();
    Ok(Merged {
        film: Film::from_sums(key.width, key.height, spp, sums.into_iter()),
        key,
        spp,
        rays,
        faults,
        render_seconds: parts.iter().map(|(_, c)| c.render_seconds).sum(),
        gaps,
        ranges: parts.iter().map(|(_, c)| range(c)).collect(),
    })
}

/// The default name of a part: `<scene stem>.samples-START-END.exr`.
pub fn default_part_name(scene: &Path, range: &Range<u64>) -> PathBuf {
    let stem = scene.file_stem().map_or_else(|| "render".into(), |s| s.to_string_lossy().into_owned());
    PathBuf::from(format!("{stem}.samples-{}-{}.exr", range.start, range.end))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_and_shards() {
        assert_eq!(parse_range("0..512"), Ok(0..512));
        assert!(parse_range("5..5").is_err());
        assert!(parse_range("a..5").is_err());
        assert!(parse_range("0..4294967297").is_err());
        assert_eq!(parse_shard("3/8"), Ok((3, 8)));
        assert!(parse_shard("8/8").is_err());
        // Equal shards tile the range exactly, also when N does not divide it.
        for (n, total) in [(8, 4096), (3, 10), (7, 1)] {
            let mut next = 0;
            for i in 0..n {
                let r = shard_range(i, n, total);
                assert_eq!(r.start, next);
                next = r.end;
            }
            assert_eq!(next, total);
        }
        assert_eq!(shard_range(1, 8, 4096), 512..1024);
    }
}
