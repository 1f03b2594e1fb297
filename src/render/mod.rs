//! Rendering: the frame loop (`frame_loop`), per-pixel accumulation on the GPU, the readback
//! into a `Film` (`film`), one render from scene to files (`job`), and checkpoints of the raw
//! accumulators for long renders that must survive interruption (`checkpoint`).

mod checkpoint;
mod film;
mod frame_loop;
mod job;

pub use checkpoint::{render_checkpointed, Checkpoint, CheckpointError, CheckpointKey, CheckpointPlan, Resume};
pub use film::Film;
pub use frame_loop::{Budget, PendingReadback, Progress, Readback, RenderError, RenderStats, Renderer, MAX_SPP};
pub use job::{
    ctrl_c_flag, default_output, method_label, progress_bar, provenance, show_progress, warm_up, OutputFiles, RenderJob, RenderOutcome,
};
