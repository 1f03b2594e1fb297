//! Watching a render from Python: Python's signal handlers and the progress callback run between
//! dispatches; a KeyboardInterrupt (or an exception in the callback) cancels the render.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use pyo3::prelude::*;

use pathlab::progress::{Reporter, Task};
use pathlab::render::{Budget, Progress};

use crate::PROGRESS_INTERVAL;

/// Comes back to Python between frames: runs its signal handlers (a KeyboardInterrupt sets
/// `cancel` and is kept to be raised once the device is idle) and calls the progress callback
/// at most every `PROGRESS_INTERVAL`.
pub(crate) struct Watch {
    pub(crate) cancel: AtomicBool,
    pub(crate) error: Mutex<Option<PyErr>>,
    pub(crate) callback: Option<Py<PyAny>>,
    pub(crate) last: Mutex<Option<Instant>>,
}

impl Watch {
    pub(crate) fn new(callback: Option<Py<PyAny>>) -> Watch {
        Watch { cancel: AtomicBool::new(false), error: Mutex::new(None), callback, last: Mutex::new(None) }
    }

    /// Runs Python's signal handlers, then the callback with `(kind, position, total, text)`
    /// if one is due (`force`: always).
    pub(crate) fn poll(&self, force: bool, kind: &'static str, position: f64, total: f64, text: impl FnOnce() -> String) {
        if self.cancel.load(Ordering::Relaxed) {
            return;
        }
        Python::attach(|py| {
            let mut result = py.check_signals();
            if result.is_ok()
                && let Some(cb) = &self.callback
            {
                let mut last = self.last.lock().unwrap_or_else(|e| e.into_inner());
                if force || last.is_none_or(|t| t.elapsed() >= PROGRESS_INTERVAL) {
                    *last = Some(Instant::now());
                    result = cb.call1(py, (kind, position, total, text())).map(|_| ());
                }
            }
            if let Err(e) = result {
                *self.error.lock().unwrap_or_else(|e| e.into_inner()) = Some(e);
                self.cancel.store(true, Ordering::Relaxed);
            }
        });
    }

    /// A render's progress: samples per pixel done of a sample budget, else seconds of a time.
    pub(crate) fn frame(&self, p: &Progress, spp_base: u64, budget: Budget) {
        let spp = p.spp_done - spp_base;
        match budget {
            Budget::Samples(n) => self.poll(false, "samples", spp as f64, n as f64, || format!("{spp} spp")),
            Budget::Time(t) => self.poll(false, "seconds", p.elapsed.as_secs_f64(), t.as_secs_f64(), || format!("{spp} spp")),
        }
    }

    /// The error a signal handler or the callback raised, if any.
    pub(crate) fn take_error(&self) -> Option<PyErr> {
        self.error.lock().unwrap_or_else(|e| e.into_inner()).take()
    }
}

/// A study's or an advice's progress, told to the Python callback as `(kind, position, text)`.
impl Reporter for Watch {
    fn stage(&self, text: &str) {
        self.poll(true, "stage", 0.0, 0.0, || text.to_string());
    }
    fn note(&self, text: &str) {
        self.poll(true, "note", 0.0, 0.0, || text.to_string());
    }
    fn warn(&self, text: &str) {
        self.poll(true, "warn", 0.0, 0.0, || text.to_string());
    }
    fn begin(&self, task: pathlab::progress::Task) {
        let (kind, total) = match task {
            Task::Samples(n) => ("begin-samples", n as f64),
            Task::Seconds(s) => ("begin-seconds", s),
            Task::Runs(n) => ("begin-runs", n as f64),
        };
        self.poll(true, kind, 0.0, total, String::new);
    }
    fn update(&self, position: f64, message: &str) {
        self.poll(false, "update", position, 0.0, || message.to_string());
    }
    fn end(&self) {
        self.poll(true, "end", 0.0, 0.0, String::new);
    }
}
