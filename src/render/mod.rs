//! Rendering: the frame loop (`frame_loop`), per-pixel accumulation on the GPU, and the
//! readback into a `Film` (`film`).

mod film;
mod frame_loop;

pub use film::Film;
pub use frame_loop::{Budget, Progress, Readback, RenderError, RenderStats, Renderer};
