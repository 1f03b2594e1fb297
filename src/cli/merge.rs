//! `pathlab merge PART.exr... -o OUT.exr`: the exact merge of sample-range parts (the work is
//! in `pathlab::shard`).

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use pathlab::output::{write_exr, Metadata};
use pathlab::render::provenance;
use pathlab::shard::merge;

#[derive(Args)]
pub struct MergeArgs {
    /// Partial files written by `render --samples` or `render --shard`.
    #[arg(required = true)]
    parts: Vec<PathBuf>,
    /// The merged image (EXR).
    #[arg(short, long)]
    output: PathBuf,
    /// Add per-pixel variance-of-the-mean channels (variance.R/G/B).
    #[arg(long)]
    variance: bool,
    /// Merge what is there even when sample ranges are missing (the header records the true
    /// spp and the gaps).
    #[arg(long)]
    allow_gaps: bool,
}

pub fn run(args: MergeArgs) -> anyhow::Result<i32> {
    let start = Instant::now();
    let merged = merge(&args.parts, args.allow_gaps)?;
    let k = &merged.key;
    let gaps: Vec<String> = merged.gaps.iter().map(|g| format!("{}..{}", g.start, g.end)).collect();
    let mut metadata: Metadata = provenance(&k.method, k.seed, k.max_depth, merged.spp, merged.rays);
    metadata.extend(
        [
            ("render_seconds", format!("{:.6}", merged.render_seconds)),
            ("scene_hash", k.scene_hash.clone()),
            ("merged_parts", args.parts.len().to_string()),
        ]
        .map(|(a, b)| (a.to_string(), b)),
    );
    if !gaps.is_empty() {
        metadata.push(("missing_samples".into(), gaps.join(",")));
    }
    write_exr(&args.output, &merged.film, &metadata, args.variance)?;
    eprintln!(
        "wrote {} ({}x{}, {} spp from {} parts, {:.3} s to merge){}",
        args.output.display(),
        k.width,
        k.height,
        merged.spp,
        args.parts.len(),
        start.elapsed().as_secs_f64(),
        if gaps.is_empty() { String::new() } else { format!("; missing samples {}", gaps.join(", ")) }
    );
    Ok(0)
}
