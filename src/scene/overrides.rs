//! Changes to a loaded scene's render settings that every front-end offers (the CLI's
//! `--width`, `--height`, `--size`, `--max-depth`, `--rr-depth`; Python's `load_scene` and
//! `Scene.with_` keywords), checked in one place before any GPU work.

use super::Scene;

/// Render settings to replace; `None` keeps the scene's.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Overrides {
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub max_depth: Option<u32>,
    /// `Some(None)`: Russian roulette off; `Some(Some(k))`: from scattering vertex `k` (>= 1).
    pub rr_depth: Option<Option<u32>>,
    /// Default samples per pixel of the scene (`render.spp`).
    pub spp: Option<u64>,
}

/// An override whose value is impossible; `field` is the setting's name in the scene file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{field} must be {requirement}")]
pub struct OverrideError {
    pub field: &'static str,
    pub requirement: &'static str,
}

impl Overrides {
    /// Checks every value, then applies them all (or none).
    pub fn apply(&self, scene: &mut Scene) -> Result<(), OverrideError> {
        let at_least_one = |field: &'static str, value: Option<u64>| match value {
            Some(0) => Err(OverrideError { field, requirement: "at least 1" }),
            _ => Ok(()),
        };
        at_least_one("width", self.width.map(u64::from))?;
        at_least_one("height", self.height.map(u64::from))?;
        at_least_one("max_depth", self.max_depth.map(u64::from))?;
        at_least_one("spp", self.spp)?;
        if self.rr_depth == Some(Some(0)) {
            return Err(OverrideError { field: "rr_depth", requirement: "at least 1 (the first scattering vertex is 1), or off" });
        }
        let r = &mut scene.render;
        r.width = self.width.unwrap_or(r.width);
        r.height = self.height.unwrap_or(r.height);
        r.max_depth = self.max_depth.unwrap_or(r.max_depth);
        r.rr_depth = self.rr_depth.unwrap_or(r.rr_depth);
        r.spp = self.spp.or(r.spp);
        Ok(())
    }
}
