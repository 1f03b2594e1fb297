//! The convergence plot: relMSE against render seconds on log-log axes (egui_plot), one curve
//! per method run since the window opened. Switching or resetting a method starts a new curve
//! and keeps the old ones, so methods can be compared at equal time.

use egui_plot::{Legend, Line, LineStyle, Plot, PlotPoints, Points};

use crate::figures::palette::curve_style;

use super::live_metrics::LivePoint;

/// One run of one method.
#[derive(Debug, Clone)]
pub struct Curve {
    pub label: String,
    pub points: Vec<LivePoint>,
}

/// Every curve drawn so far.
#[derive(Debug, Default)]
pub struct Curves {
    pub curves: Vec<Curve>,
}

impl Curves {
    /// Starts a curve for `method_name` and returns its index; a name seen before gets a run
    /// number (`mis #2`).
    pub fn start(&mut self, method_name: &str) -> usize {
        let runs = self.curves.iter().filter(|c| c.label == method_name || c.label.starts_with(&format!("{method_name} #"))).count();
        let label = if runs == 0 { method_name.to_string() } else { format!("{method_name} #{}", runs + 1) };
        self.curves.push(Curve { label, points: Vec::new() });
        self.curves.len() - 1
    }

    pub fn push(&mut self, curve: usize, point: LivePoint) {
        if let Some(c) = self.curves.get_mut(curve) {
            c.points.push(point);
        }
    }

    /// True when any point is an estimate (no reference).
    fn estimated(&self) -> bool {
        self.curves.iter().flat_map(|c| &c.points).any(|p| p.estimated)
    }
}

/// Labels a log10 axis value with the number it stands for, at 1, 2 and 5 times powers of ten
/// only (the grid has lines in between).
fn power_of_ten(log10: f64) -> String {
    let decade = 10f64.powf(log10.floor());
    let mantissa = 10f64.powf(log10) / decade;
    let Some(m) = [1.0, 2.0, 5.0, 10.0].into_iter().find(|m| (mantissa / m - 1.0).abs() < 0.01) else {
        return String::new();
    };
    let v = m * decade;
    if (0.01..1000.0).contains(&v) { format!("{}", (v * 1000.0).round() / 1000.0) } else { format!("{v:.0e}") }
}

/// Draws the plot into `ui` and returns the rectangle it occupies.
pub fn show(ui: &mut egui::Ui, curves: &Curves) -> egui::Rect {
    let y_label = if curves.estimated() {
        "est. relMSE (sample variance; no reference)"
    } else {
        "relMSE against the reference"
    };
    let plot = Plot::new("relmse-vs-seconds")
        .legend(Legend::default())
        .x_axis_label("render seconds (log)")
        .y_axis_label(y_label)
        .x_axis_formatter(|mark, _| power_of_ten(mark.value))
        .y_axis_formatter(|mark, _| power_of_ten(mark.value))
        .x_grid_spacer(egui_plot::log_grid_spacer(10))
        .y_grid_spacer(egui_plot::log_grid_spacer(10))
        .allow_scroll(false);
    let response = plot.show(ui, |plot_ui| {
        for (i, curve) in curves.curves.iter().enumerate() {
            let style = curve_style(i);
            let colour = egui::Color32::from_rgb(style.rgb[0], style.rgb[1], style.rgb[2]);
            let points: Vec<[f64; 2]> = curve
                .points
                .iter()
                .filter(|p| p.seconds > 0.0 && p.rel_mse > 0.0 && p.rel_mse.is_finite())
                .map(|p| [p.seconds.log10(), p.rel_mse.log10()])
                .collect();
            if points.is_empty() {
                continue;
            }
            let line_style = if style.dashed { LineStyle::dashed_loose() } else { LineStyle::Solid };
            plot_ui.line(Line::new(curve.label.clone(), PlotPoints::from(points.clone())).width(2.0).color(colour).style(line_style));
            plot_ui.points(Points::new(curve.label.clone(), PlotPoints::from(points)).radius(2.5).color(colour));
        }
    });
    response.response.rect
}
