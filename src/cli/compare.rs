//! `pathlab compare TEST.exr REFERENCE.exr`: every metric of one image against another.

use std::path::PathBuf;

use anyhow::{bail, Context};
use clap::Args;

use pathlab::display::{DisplayTransform, Transfer};
use pathlab::figures::error_map::write_error_map;
use pathlab::metrics::{compare, rel_mse_map, Comparison};
use pathlab::output::read_exr_image;

#[derive(Args)]
pub struct CompareArgs {
    /// The image to score (EXR).
    test: PathBuf,
    /// The reference it is scored against (EXR), e.g. a high-spp render.
    reference: PathBuf,
    /// Display transform of PSNR, SSIM and FLIP: `srgb` or `gamma:G`.
    #[arg(long, default_value = "srgb")]
    display: Transfer,
    /// Exposure in stops applied before the display transform.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    exposure: f32,
    /// Print the metrics as JSON.
    #[arg(long)]
    json: bool,
    /// Write a false-colour relative-error image (with a colour bar) here.
    #[arg(long)]
    error_map: Option<PathBuf>,
}

pub fn run(args: CompareArgs) -> anyhow::Result<i32> {
    if !args.exposure.is_finite() {
        bail!("--exposure must be finite");
    }
    let test = read_exr_image(&args.test)?;
    let reference = read_exr_image(&args.reference)?;
    let display = DisplayTransform { transfer: args.display, exposure: args.exposure };
    let result = compare(&test.film, &reference.film, display, test.has_variance && reference.has_variance)
        .with_context(|| format!("comparing {} with {}", args.test.display(), args.reference.display()))?;
    if let Some(path) = &args.error_map {
        let values = rel_mse_map(&test.film, &reference.film);
        let title = format!("relative squared error, relMSE {:.3e}", result.rel_mse);
        write_error_map(path, &values, test.film.width, test.film.height, &title)?;
        eprintln!("wrote {}", path.display());
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&result)?);
    } else {
        print_table(&result);
    }
    Ok(0)
}

fn print_table(r: &Comparison) {
    println!("size      {}x{}", r.width, r.height);
    println!("MSE       {:.6e}", r.mse);
    println!("relMSE    {:.6e}   (mean of (x - ref)^2 / (ref^2 + 0.01))", r.rel_mse);
    for (name, b) in ["R", "G", "B"].iter().zip(&r.bias) {
        match (b.std_error, b.relative_half_width(0.99)) {
            (Some(se), Some(hw)) => println!(
                "bias {name}    {:+.4e} +- {:.2e} (1 s.e.)   {:+.3}% +- {:.3}% (99%)",
                b.bias,
                se,
                100.0 * b.relative(),
                100.0 * hw
            ),
            _ => println!("bias {name}    {:+.4e}   {:+.3}%", b.bias, 100.0 * b.relative()),
        }
    }
    println!("PSNR      {:.4} dB   (display: {})", r.psnr, r.display);
    println!("SSIM      {:.5}", r.ssim);
    println!("FLIP      {:.5}", r.flip);
    match &r.z_test {
        Some(z) => println!(
            "z-test    {:.4} of {} channels pass |z| <= {:.2} (alpha {} Sidak-corrected; needs {}): {}",
            z.pass_fraction,
            z.channels,
            z.threshold,
            z.alpha,
            pathlab::metrics::Z_TEST_MIN_PASS,
            if z.passed { "consistent" } else { "DIFFERENT EXPECTATIONS" }
        ),
        None => println!("z-test    needs variance channels in both images (render --variance)"),
    }
}
