//! The header of every image pathlab writes (`pathlab:KEY` text attributes of the EXR), built
//! in one place for `render`, `merge`, the study and the viewer: what produced the image
//! (method and its parts, seed, depth, samples, rays, time, version) and of what (scene path
//! and content hash, display transform, adapter).

use std::path::PathBuf;

use crate::display::DisplayTransform;
use crate::method::Method;
use crate::output::Metadata;

/// What an image's header records.
#[derive(Debug, Clone)]
pub struct ImageHeader {
    pub method: Method,
    pub seed: u32,
    pub max_depth: u32,
    /// Russian roulette's first vertex, if any.
    pub rr_depth: Option<u32>,
    pub spp: u64,
    /// Rays traced (camera, bounce and shadow), counted by the kernel.
    pub rays: u64,
    /// Rendering time, over every session and part that contributed.
    pub render_seconds: f64,
    /// `Scene::content_hash` of the scene as rendered.
    pub scene_hash: String,
    /// The scene file, when the writer knows it (a merge knows only the parts).
    pub scene: Option<PathBuf>,
    /// The display transform of the scene's `[display]` table (how the image is meant to be shown).
    pub display: Option<DisplayTransform>,
    pub adapter: Option<String>,
    /// The researchers' techniques the method uses, with their files' SHA-256
    /// (`scene::technique::stamp`; empty for none).
    pub techniques: String,
    /// Samples in which a technique faulted and contributed 0 (`None`: not known, as for a
    /// merge, whose parts do not store them).
    pub technique_faults: Option<u64>,
}

impl ImageHeader {
    /// The attributes, in a fixed order; `extra` follows (a target's estimate, a merge's parts).
    pub fn metadata(&self, extra: &[(&str, String)]) -> Metadata {
        let mut m: Vec<(&str, String)> = vec![
            ("spp", self.spp.to_string()),
            ("method", self.method.name()),
            ("sampler", self.method.sampler.to_string()),
            ("bsdf", self.method.bsdf.to_string()),
            ("lights", self.method.lights.to_string()),
            ("seed", self.seed.to_string()),
            ("max_depth", self.max_depth.to_string()),
            ("rr_depth", super::checkpoint::rr_depth_attr(self.rr_depth)),
            ("rays", self.rays.to_string()),
            ("version", crate::VERSION.to_string()),
            ("render_seconds", format!("{:.6}", self.render_seconds)),
            ("scene_hash", self.scene_hash.clone()),
        ];
        if let Some(scene) = &self.scene {
            m.push(("scene", scene.display().to_string()));
        }
        if let Some(d) = &self.display {
            m.push(("display", d.transfer.to_string()));
            m.push(("exposure", d.exposure.to_string()));
        }
        if let Some(a) = &self.adapter {
            m.push(("adapter", a.clone()));
        }
        if !self.techniques.is_empty() {
            m.push(("techniques", self.techniques.clone()));
            if let Some(faults) = self.technique_faults {
                m.push(("technique_faults", faults.to_string()));
            }
        }
        m.extend(extra.iter().cloned());
        m.into_iter().map(|(k, v)| (k.to_string(), v)).collect()
    }
}
