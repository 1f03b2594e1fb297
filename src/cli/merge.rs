//! `pathlab merge PART.exr... -o OUT.exr`: the exact merge of sample-range parts (the work is
//! in `pathlab::shard`).

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use pathlab::output::write_exr;
use pathlab::render::ImageHeader;
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
    let gaps: Vec<String> = merged.gaps.iter().map(|g| format!("{}..{}", g.range.start, g.range.end)).collect();
    let header = ImageHeader {
        method: k.method,
        seed: k.seed,
        max_depth: k.max_depth,
        rr_depth: k.rr_depth,
        spp: merged.spp,
        rays: merged.rays,
        render_seconds: merged.render_seconds,
        scene_hash: k.scene_hash.clone(),
        scene: None,
        display: None,
        adapter: None,
        techniques: k.techniques.clone(),
        technique_faults: (!k.techniques.is_empty()).then_some(merged.faults),
    };
    let mut extra = vec![("merged_parts", args.parts.len().to_string())];
    if !gaps.is_empty() {
        extra.push(("missing_samples", gaps.join(",")));
    }
    let metadata = header.metadata(&extra);
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
