//! Figures: text in an embedded font (`text`), colour maps (`colormap`), false-colour error
//! maps with a colour bar (`error_map`), log-log convergence plots (`plot`) with the curves'
//! colours (`palette`, also the viewer's) and the study's labelled image grid (`grid`).

pub mod colormap;
pub mod error_map;
pub mod grid;
pub mod palette;
pub mod plot;
pub mod text;
