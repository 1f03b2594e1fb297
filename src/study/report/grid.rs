//! `grid.png`: seed 1 of every method at every spp beside the reference, with each method's
//! relative error map at the budget nearest the study's 10 spp.

use crate::figures::error_map::false_colour;
use crate::figures::grid::{grid, Tile};
use crate::metrics::{psnr, rel_mse_map, ssim};
use crate::output::{read_exr, write_rgb8_png};

use super::super::runs::image_path;
use super::super::{Reference, Study, StudyError};

/// The image grid; returns the spp of its error-map column.
pub fn write(study: &Study, reference: &Reference) -> Result<u64, StudyError> {
    let dir = &study.out;
    let mut spps = study.spp.clone();
    spps.sort_unstable();
    spps.dedup();
    // The error-map column shows the budget nearest the study's 10 spp.
    let error_spp = *spps.iter().min_by_key(|&&n| (n as i64 - 10).unsigned_abs()).unwrap_or(&1);
    let display = study.display;
    let ref_display = display.film(&reference.film);
    let mut headers: Vec<String> = spps.iter().map(|n| format!("{n} spp")).collect();
    headers.push("reference".into());
    headers.push(format!("rel. error, {error_spp} spp"));
    let mut rows = Vec::new();
    for m in &study.methods {
        let mut tiles = Vec::new();
        let mut error_tile = None;
        for &n in &spps {
            let film = read_exr(&image_path(dir, &m.name, n, 1)).ok().map(|(f, _)| f);
            tiles.push(film.as_ref().map(|f| {
                let img = display.film(f);
                Tile {
                    width: f.width,
                    height: f.height,
                    rgb: img.to_rgb8(),
                    label: vec![format!("{} {n} spp", m.name), format!("{:.2} dB / SSIM {:.3}", psnr(&ref_display, &img), ssim(&ref_display, &img))],
                }
            }));
            if n == error_spp {
                error_tile = film.map(|f| Tile {
                    width: f.width,
                    height: f.height,
                    rgb: false_colour(&rel_mse_map(&f, &reference.film)),
                    label: vec![format!("relMSE {:.2e}", crate::metrics::rel_mse(&f, &reference.film))],
                });
            }
        }
        tiles.push(Some(Tile {
            width: reference.film.width,
            height: reference.film.height,
            rgb: ref_display.to_rgb8(),
            // A reference from another renderer records no sample count (0).
            label: vec![if reference.film.spp > 0 { format!("reference {} spp", reference.film.spp) } else { "reference".to_string() }],
        }));
        tiles.push(error_tile);
        rows.push((if m.biased { format!("{}\n(biased demo)", m.name) } else { m.name.clone() }, tiles));
    }
    let title = format!("{} ({}), display {}", study.scene_path.display(), study.scene.content_hash(), display);
    let canvas = grid(&title, &headers, rows);
    write_rgb8_png(&dir.join("grid.png"), canvas.width, canvas.height, canvas.pixels)?;
    Ok(error_spp)
}
