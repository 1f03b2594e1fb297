//! The checks of single values that every part of validation shares (the scene's tables in
//! `validate`, the BSDF kinds' fields in `bsdfs`): each finding names the file, the line and the
//! field, and all findings of a file are collected.

use std::ops::Range;
use std::path::Path;

use glam::DVec3;
use toml::Spanned;

use super::diagnostic::SourceMap;
use super::raw::RawColor;
use super::{Diagnostic, Severity};

pub(super) struct Checker<'a> {
    /// The scene file (mesh files are relative to its directory).
    pub(super) file: &'a Path,
    /// Where the spans of the raw scene point: the TOML file, or a Mitsuba file and its includes.
    pub(super) sources: SourceMap,
    pub(super) diagnostics: Vec<Diagnostic>,
}

impl<'a> Checker<'a> {
    fn report(&mut self, severity: Severity, span: Range<usize>, field: impl Into<String>, message: impl Into<String>) {
        let d = self.sources.diagnostic(severity, span.start, field.into(), message.into());
        self.diagnostics.push(d);
    }

    pub(super) fn error(&mut self, span: Range<usize>, field: impl Into<String>, message: impl Into<String>) {
        self.report(Severity::Error, span, field, message);
    }

    pub(super) fn warn(&mut self, span: Range<usize>, field: impl Into<String>, message: impl Into<String>) {
        self.report(Severity::Warning, span, field, message);
    }

    /// A finite number that also fits in f32 (the GPU's precision).
    pub(super) fn number(&mut self, value: &Spanned<f64>, field: &str) -> f64 {
        let v = *value.get_ref();
        if !v.is_finite() {
            self.error(value.span(), field, format!("must be a finite number (got {v})"));
            return 0.0;
        }
        if v.abs() > f32::MAX as f64 {
            self.error(value.span(), field, format!("{v} is too large for 32-bit floats"));
            return 0.0;
        }
        v
    }

    pub(super) fn vector(&mut self, value: &Spanned<[f64; 3]>, field: &str) -> DVec3 {
        let span = value.span();
        let mut out = [0.0; 3];
        for (o, &v) in out.iter_mut().zip(value.get_ref()) {
            *o = self.number(&Spanned::new(span.clone(), v), field);
        }
        DVec3::from_array(out)
    }

    /// A colour: finite and non-negative in every channel.
    pub(super) fn color(&mut self, value: Option<&Spanned<RawColor>>, field: &str) -> DVec3 {
        let Some(value) = value else { return DVec3::ZERO };
        let c = self.vector(&Spanned::new(value.span(), value.get_ref().0), field);
        if c.min_element() < 0.0 {
            self.error(value.span(), field, format!("colour channels must be >= 0 (got {:?})", c.to_array()));
            return DVec3::ZERO;
        }
        c
    }

    pub(super) fn integer(&mut self, value: &Spanned<i64>, field: &str, min: i64, max: i64) -> u64 {
        let v = *value.get_ref();
        if v < min || v > max {
            self.error(value.span(), field, format!("must be between {min} and {max} (got {v})"));
            return min.max(1) as u64;
        }
        v as u64
    }
}

