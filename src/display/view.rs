//! What an image area shows (the viewer's views, `pathlab view --view`) and the log10 ranges of
//! the false-colour maps, shared by the viewer's display pass, `compare --error-map` and the
//! study's grid.

use crate::names::named_enum;

/// The log10 range of relative squared error maps: errors at or below 10^LOW are black, at or
/// above 10^HIGH white-ish.
pub const LOG10_RANGE: (f64, f64) = (-4.0, 1.0);

named_enum! {
    /// What an image area shows: the radiance, or a false-colour map of its error. The values
    /// of the display pass's `VIEW_*` constants are generated from these.
    pub enum View("view") {
        /// The mean radiance through exposure and display transform.
        Radiance = "radiance",
        /// Per-pixel relative standard error of the mean, sqrt(var / (mean^2 - var + 0.01)).
        RelStderr = "stderr",
        /// |mean - reference|, averaged over the channels (needs a reference).
        AbsError = "abs-error",
        /// (mean - reference)^2 / (reference^2 + 0.01): the terms of relMSE (needs a reference).
        RelError = "rel-error",
    }
}

impl View {
    /// What the panel calls it.
    pub fn label(self) -> &'static str {
        match self {
            View::Radiance => "radiance",
            View::RelStderr => "relative standard error",
            View::AbsError => "absolute error",
            View::RelError => "relative squared error",
        }
    }

    pub fn needs_reference(self) -> bool {
        matches!(self, View::AbsError | View::RelError)
    }

    /// The log10 range of a false-colour view (errors below the low end are black).
    pub fn log10_range(self) -> (f32, f32) {
        match self {
            View::Radiance => (0.0, 1.0),
            View::RelStderr => (-3.0, 0.0),
            View::AbsError => (-4.0, 0.0),
            View::RelError => (LOG10_RANGE.0 as f32, LOG10_RANGE.1 as f32),
        }
    }

}
