//! Progress of long library operations, told through a trait the front-end implements: the
//! CLI draws bars and prints stages on stderr, the viewer and the Python bindings do their own,
//! tests stay silent. The library itself prints nothing.

/// A piece of work whose progress is shown as it goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Task {
    /// Samples per pixel to render; `update` positions are spp.
    Samples(u64),
    /// Seconds to render for; `update` positions are seconds, the message says the spp.
    Seconds(f64),
    /// Runs of a study; `update` positions are finished runs, the message names the next one.
    Runs(u64),
}

/// What a long operation tells its user. Every method has a silent default.
pub trait Reporter {
    /// A stage of a multi-step operation begins (`[1/4] reference`).
    fn stage(&self, _text: &str) {}
    /// A line worth telling (a reused cache, where a checkpoint went).
    fn note(&self, _text: &str) {}
    /// Something the user should act on (a reference too noisy for the errors it scores).
    fn warn(&self, _text: &str) {}
    /// `task` starts; `update` follows it, `end` closes it.
    fn begin(&self, _task: Task) {}
    fn update(&self, _position: f64, _message: &str) {}
    fn end(&self) {}
}

/// Tells nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Reporter for Silent {}
