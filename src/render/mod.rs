//! Rendering: the `renderer` and its parts (`band`, `batch`, `interactive`, `readback`,
//! `timestamps`), the `controller` that sizes sample counts to time spans, the loop that renders
//! to a target error (`to_target`), checkpoints of the raw accumulators for long renders that
//! must survive interruption (`checkpoint`), the image header (`header`), and one render from
//! scene to files (`job`).

mod band;
mod batch;
mod checkpoint;
pub mod controller;
mod header;
mod interactive;
mod job;
mod readback;
mod renderer;
mod timestamps;
pub mod to_target;

pub use checkpoint::{render_checkpointed, Checkpoint, CheckpointError, CheckpointKey, CheckpointPlan, Resume};
pub use header::ImageHeader;
pub use job::{ctrl_c_flag, default_output, warm_up, ErrorPlan, ErrorTrack, OutputFiles, RenderJob, RenderOutcome};
pub use readback::{PendingReadback, Readback};
pub use renderer::{Budget, Progress, RenderError, RenderStats, Renderer, MAX_SPP};
