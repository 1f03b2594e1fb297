//! The command line's `Reporter`: stages and notes on stderr, progress bars (indicatif) while a
//! terminal watches, nothing drawn with `--quiet` or when stderr is not a terminal.

use std::io::IsTerminal;
use std::sync::Mutex;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use pathlab::progress::{Reporter, Task};
use pathlab::render::{Budget, Progress};

/// Prints stages, notes and warnings; draws one bar at a time.
pub struct Terminal {
    quiet: bool,
    bar: Mutex<Option<(ProgressBar, Task)>>,
}

impl Terminal {
    pub fn new(quiet: bool) -> Terminal {
        Terminal { quiet, bar: Mutex::new(None) }
    }

    /// Shows a render's progress report on the bar of `budget` (begun by `begin_budget`).
    pub fn frame(&self, p: Progress) {
        // (A render to a target error shows its estimate on a spinner of its own, cli/render.rs.)
        let message = format!("{} spp", p.spp_done);
        let by_time = matches!(self.bar.lock().unwrap_or_else(|e| e.into_inner()).as_ref(), Some((_, Task::Seconds(_))));
        self.update(if by_time { p.elapsed.as_secs_f64() } else { p.spp_done as f64 }, &message);
    }

    /// Begins the bar of a render with `budget`.
    pub fn begin_budget(&self, budget: Budget) {
        self.begin(match budget {
            Budget::Samples(n) => Task::Samples(n),
            Budget::Time(t) => Task::Seconds(t.as_secs_f64()),
        });
    }
}

impl Reporter for Terminal {
    fn stage(&self, text: &str) {
        eprintln!("{text}");
    }

    fn note(&self, text: &str) {
        eprintln!("{text}");
    }

    fn warn(&self, text: &str) {
        eprintln!("warning: {text}");
    }

    fn begin(&self, task: Task) {
        let (len, template) = match task {
            Task::Samples(n) => (n, "{bar:40} {pos}/{len} spp  {per_sec}  ETA {eta}"),
            Task::Seconds(t) => ((t * 1000.0) as u64, "{bar:40} {msg}  {elapsed} / {duration}"),
            Task::Runs(n) => (n, "{bar:40} {pos}/{len} runs  {msg}  ETA {eta}"),
        };
        let bar = ProgressBar::new(len).with_style(ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()));
        if self.quiet || !std::io::stderr().is_terminal() {
            bar.set_draw_target(ProgressDrawTarget::hidden());
        }
        *self.bar.lock().unwrap_or_else(|e| e.into_inner()) = Some((bar, task));
    }

    fn update(&self, position: f64, message: &str) {
        if let Some((bar, task)) = self.bar.lock().unwrap_or_else(|e| e.into_inner()).as_ref() {
            bar.set_position(match task {
                Task::Seconds(_) => (position * 1000.0) as u64,
                _ => position as u64,
            });
            bar.set_message(message.to_string());
        }
    }

    fn end(&self) {
        if let Some((bar, _)) = self.bar.lock().unwrap_or_else(|e| e.into_inner()).take() {
            bar.finish_and_clear();
        }
    }
}
