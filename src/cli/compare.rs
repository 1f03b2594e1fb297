//! `pathlab compare TEST.exr REFERENCE.exr`: every metric of one image against another.

use std::path::PathBuf;

use anyhow::{bail, Context};
use clap::Args;

use pathlab::display::{DisplayTransform, Transfer};
use pathlab::figures::error_map::write_error_map;
use pathlab::metrics::{compare_blocks, rel_mse_map, Comparison};
use pathlab::output::read_exr_image;

#[derive(Args)]
pub struct CompareArgs {
    /// The image to score (EXR).
    test: PathBuf,
    /// The reference it is scored against (EXR), e.g. a high-spp render.
    reference: PathBuf,
    /// Display transform of PSNR, SSIM and FLIP: `srgb` or `gamma:G` (default: the one the
    /// reference's header records, from its scene's [display] table; else srgb).
    #[arg(long)]
    display: Option<Transfer>,
    /// Exposure in stops applied before the display transform (default: the reference's
    /// header, else 0).
    #[arg(long, allow_negative_numbers = true)]
    exposure: Option<f32>,
    /// Run the z-test on BxB pixel blocks (for methods without light sampling, whose per-pixel
    /// estimates are too heavy-tailed for a normal approximation at moderate spp).
    #[arg(long, default_value_t = 1)]
    block: u32,
    /// Print the metrics as JSON.
    #[arg(long)]
    json: bool,
    /// Write a false-colour relative-error image (with a colour bar) here.
    #[arg(long)]
    error_map: Option<PathBuf>,
}

pub fn run(args: CompareArgs) -> anyhow::Result<i32> {
    if args.exposure.is_some_and(|e| !e.is_finite()) {
        bail!("--exposure must be finite");
    }
    let test = read_exr_image(&args.test)?;
    let reference = read_exr_image(&args.reference)?;
    // The reference's recorded display transform, used unless overridden: a value that does not
    // parse is refused where it would be used, and named with a warning where it is not.
    let recorded = |key: &str| reference.metadata.iter().find(|(k, _)| k == key).map(|(_, v)| v.clone());
    let refuse = |key: &str, value: &str, why: String| -> anyhow::Error {
        anyhow::anyhow!("{}: pathlab:{key} is `{value}`: {why} (or give --{key})", args.reference.display())
    };
    let recorded_transfer = recorded("display").map(|t| t.parse::<Transfer>().map_err(|e| refuse("display", &t, e.to_string())));
    let recorded_exposure = recorded("exposure").map(|e| match e.trim().parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(refuse("exposure", &e, "not a finite number of stops".into())),
    });
    let transfer = match (args.display, recorded_transfer) {
        (Some(t), Some(Err(e))) => {
            eprintln!("warning: {e:#}; using --display {t}");
            t
        }
        (Some(t), _) => t,
        (None, Some(r)) => r?,
        (None, None) => Transfer::Srgb,
    };
    let exposure = match (args.exposure, recorded_exposure) {
        (Some(x), Some(Err(e))) => {
            eprintln!("warning: {e:#}; using --exposure {x}");
            x
        }
        (Some(x), _) => x,
        (None, Some(r)) => r?,
        (None, None) => 0.0,
    };
    let display = DisplayTransform { transfer, exposure };
    let result = compare_blocks(&test.film, &reference.film, display, test.has_variance && reference.has_variance, args.block)
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
    println!("PSNR      {:.4} dB   (display: {}; display MSE {:.4e})", r.psnr, r.display, r.display_mse);
    if let (Some(mse), Some(p)) = (r.expected_display_mse, r.expected_psnr) {
        println!("noise     {p:.4} dB   (display MSE {mse:.4e}: what the two images' variances alone give; a PSNR near it is their noise floor, not a bias test)");
    }
    println!("SSIM      {:.5}", r.ssim);
    println!("FLIP      {:.5}", r.flip);
    match &r.z_test {
        Some(z) => println!(
            "z-test    {:.4} of {} channels{} pass |z| <= {:.2} (alpha {} Sidak-corrected; needs {}): {}",
            z.pass_fraction,
            z.channels,
            if z.block > 1 { format!(" of {0}x{0} blocks", z.block) } else { String::new() },
            z.threshold,
            z.alpha,
            pathlab::metrics::Z_TEST_MIN_PASS,
            if z.passed { "consistent" } else { "DIFFERENT EXPECTATIONS" }
        ),
        None => println!("z-test    needs variance channels in both images (render --variance)"),
    }
}
