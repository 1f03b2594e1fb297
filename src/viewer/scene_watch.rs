//! Watching the scene file: its modification time and length are compared every frame (one
//! `stat`, no extra thread), and a change reloads and re-validates it.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

use crate::scene::{Scene, SceneError};

/// The scene file and what it looked like when last read.
pub struct SceneWatch {
    path: PathBuf,
    /// `--define`s of a Mitsuba scene, applied to every reload.
    defines: Vec<(String, String)>,
    seen: Option<(SystemTime, u64)>,
}

fn stamp(path: &Path) -> Option<(SystemTime, u64)> {
    let meta = std::fs::metadata(path).ok()?;
    Some((meta.modified().ok()?, meta.len()))
}

impl SceneWatch {
    /// Watches `path` (a Mitsuba scene's main file; its includes are not watched), taking its
    /// present state as already loaded.
    pub fn new(path: &Path, defines: &[(String, String)]) -> SceneWatch {
        SceneWatch { path: path.to_path_buf(), defines: defines.to_vec(), seen: stamp(path) }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// `Some(result of loading it)` when the file changed since the last call; `None` when it
    /// did not (or is mid-replacement and cannot be read yet).
    pub fn poll(&mut self) -> Option<Result<Scene, SceneError>> {
        let now = stamp(&self.path);
        if now.is_none() || now == self.seen {
            return None;
        }
        self.seen = now;
        Some(Scene::load_with(&self.path, &self.defines))
    }
}
