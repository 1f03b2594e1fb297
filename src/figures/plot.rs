//! Log-log convergence plots (plotters, drawn into memory with the embedded font and written
//! as PNG): one colour per method, its runs as points and its least-squares fit as a line.

use std::path::Path;

use plotters::element::DashedPathElement;
use plotters::prelude::*;

use crate::output::{write_rgb8_png, OutputError};

use super::palette::curve_style;
use super::text::FONT_BYTES;

/// One method's points and fitted line ln y = intercept + slope ln x.
#[derive(Debug, Clone)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub fit: Option<(f64, f64)>,
}

const SIZE: (u32, u32) = (900, 600);

fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT_BYTES);
    });
}

/// Draws the plot and writes it to `path` (atomically).
pub fn write_log_log(path: &Path, title: &str, x_label: &str, y_label: &str, series: &[Series]) -> Result<(), OutputError> {
    register_font();
    let encode = |message: String| OutputError::Encode { path: path.to_path_buf(), message };
    let all: Vec<(f64, f64)> = series.iter().flat_map(|s| s.points.iter().copied()).filter(|(x, y)| *x > 0.0 && *y > 0.0).collect();
    if all.is_empty() {
        return Err(encode("nothing to plot".into()));
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (x, y) in &all {
        (x0, x1, y0, y1) = (x0.min(*x), x1.max(*x), y0.min(*y), y1.max(*y));
    }
    let (x0, x1, y0, y1) = (x0 / 1.5, x1 * 1.5, y0 / 2.0, y1 * 2.0);
    let mut buffer = vec![255u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, SIZE).into_drawing_area();
        let draw = || -> Result<(), Box<dyn std::error::Error + '_>> {
            root.fill(&WHITE)?;
            let mut chart = ChartBuilder::on(&root)
                .caption(title, ("sans-serif", 20))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(80)
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
            chart
                .configure_mesh()
                .x_desc(x_label)
                .y_desc(y_label)
                .x_label_formatter(&|v| format!("{v:.3}").trim_end_matches('0').trim_end_matches('.').to_string())
                .y_label_formatter(&|v| format!("{v:.0e}"))
                .label_style(("sans-serif", 13))
                .draw()?;
            for (i, s) in series.iter().enumerate() {
                let style = curve_style(i);
                let colour = RGBColor(style.rgb[0], style.rgb[1], style.rgb[2]).to_rgba();
                let label = match s.fit {
                    Some((slope, _)) => format!("{} (slope {slope:.2})", s.name),
                    None => s.name.clone(),
                };
                let points = s.points.iter().filter(|(x, y)| *x > 0.0 && *y > 0.0);
                // Beyond the palette's ten colours: dashed lines and hollow markers.
                let legend = move |(x, y): (i32, i32)| {
                    let ends = vec![(x, y), (x + 20, y)];
                    if style.dashed {
                        DashedPathElement::new(ends, 5, 3, colour.stroke_width(2)).into_dyn()
                    } else {
                        PathElement::new(ends, colour.stroke_width(2)).into_dyn()
                    }
                };
                let marker = if style.dashed { colour.stroke_width(1) } else { colour.filled() };
                chart.draw_series(points.map(|&(x, y)| Circle::new((x, y), 3, marker)))?.label(label).legend(legend);
                if let Some((slope, intercept)) = s.fit {
                    let (lo, hi) = s.points.iter().fold((f64::MAX, f64::MIN), |(lo, hi), (x, _)| (lo.min(*x), hi.max(*x)));
                    let at = |x: f64| (intercept + slope * x.ln()).exp();
                    let line = [(lo, at(lo)), (hi, at(hi))];
                    if style.dashed {
                        chart.draw_series(DashedLineSeries::new(line, 8, 5, colour.stroke_width(2)))?;
                    } else {
                        chart.draw_series(LineSeries::new(line, colour.stroke_width(1)))?;
                    }
                }
            }
            chart
                .configure_series_labels()
                .label_font(("sans-serif", 13))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .position(SeriesLabelPosition::LowerLeft)
                .draw()?;
            root.present()?;
            Ok(())
        };
        draw().map_err(|e| encode(e.to_string()))?;
    }
    write_rgb8_png(path, SIZE.0, SIZE.1, buffer)
}
