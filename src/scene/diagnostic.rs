//! Errors and warnings about a scene file, each naming the file, the line and the field.

use std::fmt;
use std::path::PathBuf;

/// Error or warning.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Severity {
    Error,
    Warning,
}

/// One finding about a scene file: where it is (file, 1-based line and column, dotted field
/// path such as `spheres[2].radius`) and what is wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    pub severity: Severity,
    pub file: PathBuf,
    pub line: usize,
    pub column: usize,
    pub field: String,
    pub message: String,
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        // Line 0: a finding about a whole file (e.g. in a binary mesh file), without a position.
        if self.line == 0 {
            write!(f, "{}: {kind}: ", self.file.display())?;
        } else {
            write!(f, "{}:{}:{}: {kind}: ", self.file.display(), self.line, self.column)?;
        }
        if !self.field.is_empty() {
            write!(f, "`{}`: ", self.field)?;
        }
        write!(f, "{}", self.message)
    }
}

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The cause is part of the message (not a `source`, which a caller printing the chain
    /// would print a second time).
    #[error("cannot read scene file {}: {cause}", path.display())]
    Io { path: PathBuf, cause: std::io::Error },
    #[error("{}", format_errors(.0))]
    Invalid(Vec<Diagnostic>),
}

impl SceneError {
    /// The diagnostics of an invalid scene (empty for I/O errors).
    pub fn diagnostics(&self) -> &[Diagnostic] {
        match self {
            SceneError::Io { .. } => &[],
            SceneError::Invalid(d) => d,
        }
    }
}

fn format_errors(diagnostics: &[Diagnostic]) -> String {
    let lines: Vec<String> = diagnostics.iter().map(ToString::to_string).collect();
    lines.join("\n")
}

/// Maps byte offsets of a source text to 1-based (line, column).
#[derive(Clone)]
pub(crate) struct LineIndex {
    line_starts: Vec<usize>,
}

impl LineIndex {
    pub(crate) fn new(text: &str) -> Self {
        let mut line_starts = vec![0];
        line_starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        LineIndex { line_starts }
    }

    pub(crate) fn line_column(&self, offset: usize) -> (usize, usize) {
        let line = self.line_starts.partition_point(|&start| start <= offset);
        let start = self.line_starts[line.saturating_sub(1)];
        (line.max(1), offset - start + 1)
    }
}

/// The text files a scene was read from (a Mitsuba file and its includes; one TOML file), laid
/// end to end: a global byte offset names one file and a position in it, so that spans from
/// any of them can travel in one `Spanned` and still name file, line and column.
#[derive(Default, Clone)]
pub(crate) struct SourceMap {
    files: Vec<SourceFile>,
}

#[derive(Clone)]
struct SourceFile {
    path: PathBuf,
    base: usize,
    len: usize,
    lines: LineIndex,
}

impl SourceMap {
    pub(crate) fn single(path: &std::path::Path, text: &str) -> SourceMap {
        let mut map = SourceMap::default();
        map.add(path, text);
        map
    }

    /// Adds a file; returns the global offset of its first byte.
    pub(crate) fn add(&mut self, path: &std::path::Path, text: &str) -> usize {
        let base = self.files.last().map_or(0, |f| f.base + f.len + 1);
        self.files.push(SourceFile { path: path.to_path_buf(), base, len: text.len(), lines: LineIndex::new(text) });
        base
    }

    /// File, 1-based line and column of a global offset.
    pub(crate) fn locate(&self, offset: usize) -> (PathBuf, usize, usize) {
        let i = self.files.partition_point(|f| f.base <= offset).saturating_sub(1);
        match self.files.get(i) {
            Some(f) => {
                let (line, column) = f.lines.line_column((offset - f.base.min(offset)).min(f.len));
                (f.path.clone(), line, column)
            }
            None => (PathBuf::new(), 0, 0),
        }
    }

    pub(crate) fn diagnostic(&self, severity: Severity, offset: usize, field: String, message: String) -> Diagnostic {
        let (file, line, column) = self.locate(offset);
        Diagnostic { severity, file, line, column, field, message }
    }
}

/// Collects the findings of a reader whose offsets point into a `SourceMap`.
pub(crate) trait Findings {
    fn sources(&self) -> &SourceMap;
    fn findings(&mut self) -> &mut Vec<Diagnostic>;

    fn error(&mut self, at: usize, field: impl Into<String>, message: impl Into<String>) {
        let d = self.sources().diagnostic(Severity::Error, at, field.into(), message.into());
        self.findings().push(d);
    }

    fn warn(&mut self, at: usize, field: impl Into<String>, message: impl Into<String>) {
        let d = self.sources().diagnostic(Severity::Warning, at, field.into(), message.into());
        self.findings().push(d);
    }
}
