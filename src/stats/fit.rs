//! Power-law fits: least squares of log y against log x, the model of Monte Carlo convergence
//! (error = a N^b, b = -1 for independent samples) used by the study's convergence table and by
//! `advise`'s predictions.

use serde::Serialize;

/// log y = intercept + slope log x (natural logs), least squares.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Fit {
    pub slope: f64,
    pub intercept: f64,
    /// Coefficient of determination.
    pub r2: f64,
    pub points: usize,
    /// Largest x fitted.
    pub x_max: f64,
}

/// `Fit::solve` extrapolates at most this factor beyond the largest x measured.
pub const MAX_EXTRAPOLATION: f64 = 100.0;

impl Fit {
    /// Least squares through (ln x, ln y) of the positive points; `None` with fewer than two
    /// distinct x.
    pub fn log_log(points: &[(f64, f64)]) -> Option<Fit> {
        let pts: Vec<(f64, f64)> = points.iter().filter(|(x, y)| *x > 0.0 && *y > 0.0).map(|(x, y)| (x.ln(), y.ln())).collect();
        let n = pts.len() as f64;
        let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
        let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
        let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
        let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        let syy: f64 = pts.iter().map(|p| (p.1 - my).powi(2)).sum();
        if pts.len() < 2 || sxx <= 1e-12 {
            return None;
        }
        let slope = sxy / sxx;
        let r2 = if syy > 0.0 { (sxy * sxy) / (sxx * syy) } else { 1.0 };
        let x_max = pts.iter().map(|p| p.0).fold(f64::MIN, f64::max).exp();
        Some(Fit { slope, intercept: my - slope * mx, r2, points: pts.len(), x_max })
    }

    /// The fitted y at x.
    pub fn at(&self, x: f64) -> f64 {
        (self.intercept + self.slope * x.ln()).exp()
    }

    /// The x at which the fit reaches `target`: only for decreasing fits, and only up to
    /// `MAX_EXTRAPOLATION` times the largest x measured (beyond, the fit says nothing).
    pub fn solve(&self, target: f64) -> Option<f64> {
        if !(self.slope < 0.0 && target > 0.0) {
            return None;
        }
        let x = ((target.ln() - self.intercept) / self.slope).exp();
        (x <= MAX_EXTRAPOLATION * self.x_max).then_some(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_log_fit_recovers_a_power_law() {
        let pts: Vec<(f64, f64)> = [1.0, 4.0, 16.0, 64.0].iter().map(|&x| (x, 2.0 * f64::powf(x, -1.0))).collect();
        let f = Fit::log_log(&pts).unwrap();
        assert!((f.slope + 1.0).abs() < 1e-12 && (f.intercept - 2f64.ln()).abs() < 1e-12 && (f.r2 - 1.0).abs() < 1e-12);
        assert!((f.solve(0.02).unwrap() - 100.0).abs() < 1e-9);
        // Beyond 100x the largest x measured (64), no prediction.
        assert!(f.solve(2.0 / 6399.0).is_some() && f.solve(2.0 / 6500.0).is_none());
        assert!((f.at(8.0) - 0.25).abs() < 1e-12);
        assert!(Fit::log_log(&[(1.0, 1.0)]).is_none());
    }

}
