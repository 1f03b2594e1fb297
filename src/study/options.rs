//! A study's settings as a front-end gives them (the CLI's flags, Python's keywords), each
//! optional, with the defaults of a full and of a quick study kept here, made into a `Study`.

use std::path::PathBuf;
use std::time::Duration;

use crate::display::{DisplayTransform, Transfer};
use crate::method::Preset;
use crate::scene::{Overrides, Scene};

use super::{ReferenceSource, Study, StudyError, StudyMethod};

/// What a study is asked for; `None` takes the default (a quick study's with `quick`).
#[derive(Debug, Clone, Default)]
pub struct StudyOptions {
    /// Method names: presets and the biased demonstrations (default: every preset).
    pub methods: Option<Vec<String>>,
    /// Budgets of the equal-sample table (default 1,4,10,64,1000; quick 1,4,10,64,256).
    pub spp: Option<Vec<u64>>,
    /// Budgets of the equal-time table in seconds (default 0.5,2,8; quick 0.1,0.3).
    pub times: Option<Vec<f64>>,
    /// Seeds per cell (default 3; quick 2).
    pub seeds: Option<u32>,
    /// A reference EXR to load instead of rendering one.
    pub reference: Option<PathBuf>,
    /// Samples per pixel of a rendered reference (default 100000; quick 4096).
    pub reference_spp: Option<u64>,
    /// Method of a rendered reference (default `default_reference_method`: `best`, or
    /// `best+env` under an environment map).
    pub reference_method: Option<String>,
    /// Image size (default: the reference file's, else quick's (`quick_size`), else the scene's).
    pub size: Option<(u32, u32)>,
    pub max_depth: Option<u32>,
    /// `Some(None)`: Russian roulette off.
    pub rr_depth: Option<Option<u32>>,
    /// Display transform of the display-referred metrics (default: the scene's).
    pub display: Option<Transfer>,
    /// Target relMSE of the time-to-target column.
    pub target: Option<f64>,
    /// A regions file (`study::regions`).
    pub regions: Option<PathBuf>,
    /// Interval between checkpoints of the reference render (default 5 minutes).
    pub checkpoint_every: Option<Duration>,
    /// The small study for trying things out and for CI.
    pub quick: bool,
}

impl StudyOptions {
    /// The study of `scene` (read from `scene_path`) into `out`; `command` is how it was asked
    /// for, for the report. Checks names and sizes; `Study::validate` checks the rest.
    pub fn study(&self, mut scene: Scene, scene_path: PathBuf, out: PathBuf, command: String) -> Result<Study, StudyError> {
        let q = self.quick;
        let methods = match &self.methods {
            Some(names) => names.iter().map(|n| StudyMethod::by_name(n.trim())).collect::<Result<Vec<_>, _>>()?,
            None => default_methods(&scene).iter().map(|n| StudyMethod::by_name(n)).collect::<Result<Vec<_>, _>>()?,
        };
        // Methods that cannot see one of the scene's lights (a delta light without next event
        // estimation) are left out, each with its reason.
        let (methods, blind): (Vec<StudyMethod>, Vec<StudyMethod>) = methods.into_iter().partition(|m| scene.why_left_out(&m.method).is_none());
        let left_out: Vec<String> = blind.iter().filter_map(|m| scene.why_left_out(&m.method)).collect();
        if methods.is_empty() {
            return Err(StudyError::Input(format!("no method left to study: {}", left_out.join("; "))));
        }
        let reference = match &self.reference {
            Some(path) => ReferenceSource::File(path.clone()),
            None => {
                let m = StudyMethod::by_name(self.reference_method.as_deref().unwrap_or(default_reference_method(&scene)))?;
                if m.biased {
                    return Err(StudyError::Input(format!("reference method {} is a biased demonstration; a reference must be unbiased", m.name)));
                }
                if let Some(light) = scene.delta_light_unseen_by(&m.method) {
                    return Err(StudyError::Input(format!("reference method {} cannot see {light} (a delta light is found only by next event estimation)", m.name)));
                }
                ReferenceSource::Render { method: m.method, spp: self.reference_spp.unwrap_or(if q { 4096 } else { 100_000 }) }
            }
        };
        // Size: given, else the reference file's, else quick's, else the scene's.
        let file_size = match &self.reference {
            Some(p) if self.size.is_none() => {
                let (film, _) = crate::output::read_exr(p)?;
                Some((film.width, film.height))
            }
            _ => None,
        };
        let size = self.size.or(file_size).or(q.then(|| quick_size(scene.render.width, scene.render.height)));
        let overrides =
            Overrides { width: size.map(|s| s.0), height: size.map(|s| s.1), max_depth: self.max_depth, rr_depth: self.rr_depth, spp: None };
        let reframing = overrides.apply(&mut scene)?;
        let display = match self.display {
            Some(transfer) => DisplayTransform { transfer, ..scene.display },
            None => scene.display,
        };
        let regions = match &self.regions {
            Some(path) => super::regions::load(path, scene.render.width, scene.render.height)?,
            None => Vec::new(),
        };
        Ok(Study {
            scene,
            scene_path,
            out,
            methods,
            spp: self.spp.clone().unwrap_or_else(|| if q { vec![1, 4, 10, 64, 256] } else { vec![1, 4, 10, 64, 1000] }),
            times: self.times.clone().unwrap_or_else(|| if q { vec![0.1, 0.3] } else { vec![0.5, 2.0, 8.0] }),
            seeds: self.seeds.unwrap_or(if q { 2 } else { 3 }),
            reference,
            regions,
            display,
            target: self.target,
            checkpoint_every: self.checkpoint_every.unwrap_or(Duration::from_secs(300)),
            command,
            reframing,
            left_out,
        })
    }
}

/// The methods `study` and `advise` compare when none are named: every preset; under an
/// environment map that is a light, also its sampling strategies, each without MIS (`nee`)
/// and with it (`mis`): uniform, luminance, and MIS-compensated, which needs MIS
/// (`nee+env+env-uniform`, `nee+env`, `mis+env+env-uniform`, `mis+env`,
/// `mis+env+env-compensated`).
pub fn default_methods(scene: &Scene) -> Vec<String> {
    let mut names: Vec<String> = Preset::ALL.iter().map(|p| p.name().to_string()).collect();
    if scene.environment_map.as_ref().is_some_and(|m| !m.is_black()) {
        names.extend(["nee+env+env-uniform", "nee+env", "mis+env+env-uniform", "mis+env", "mis+env+env-compensated"].map(String::from));
    }
    names
}

/// The method of a rendered reference when none is named: every command's default
/// (`Scene::default_method_name`: `best`, and `best+env` under an environment map).
pub fn default_reference_method(scene: &Scene) -> &'static str {
    scene.default_method_name()
}

/// A quick study's image size: the scene's aspect ratio, its longer side 128 pixels and the
/// other rounded to a whole pixel (at least 1).
pub fn quick_size(width: u32, height: u32) -> (u32, u32) {
    const LONGER: u32 = 128;
    let short = |a: u32, b: u32| ((LONGER as f64 * a as f64 / b as f64).round() as u32).max(1);
    if width >= height { (LONGER, short(height, width)) } else { (short(width, height), LONGER) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cornell_box() -> (Scene, PathBuf) {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/cornell_box.toml");
        (Scene::load(&path).unwrap(), path)
    }

    /// The study renders `study.scene` at its size: the quick study of the square Cornell box
    /// is square (it was 128x64, cutting off the ceiling light), and keeps the framing.
    #[test]
    fn a_square_scenes_quick_study_renders_square_images() {
        let (scene, path) = cornell_box();
        let quick = StudyOptions { quick: true, ..StudyOptions::default() };
        let study = quick.study(scene.clone(), path.clone(), "out".into(), String::new()).unwrap();
        assert_eq!((study.scene.render.width, study.scene.render.height), (128, 128));
        assert_eq!(study.reframing, None);
        // A size of another aspect ratio is the user's to choose, and is told.
        let wide = StudyOptions { quick: true, size: Some((128, 64)), ..StudyOptions::default() };
        let study = wide.study(scene, path, "out".into(), String::new()).unwrap();
        assert_eq!((study.scene.render.width, study.scene.render.height), (128, 64));
        assert!(study.reframing.expect("a reframing").to_string().contains("less is seen above and below"));
    }

    #[test]
    fn the_quick_size_keeps_the_aspect_ratio() {
        assert_eq!(quick_size(512, 256), (128, 64));
        assert_eq!(quick_size(256, 256), (128, 128));
        assert_eq!(quick_size(1920, 1080), (128, 72));
        assert_eq!(quick_size(600, 800), (96, 128));
        assert_eq!(quick_size(10_000, 1), (128, 1));
    }

    #[test]
    fn an_environment_map_adds_its_strategies_and_a_reference_that_samples_it() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let study = Scene::load(root.join("assets/scenes/study.toml")).unwrap();
        let presets: Vec<String> = Preset::ALL.iter().map(|p| p.name().to_string()).collect();
        assert_eq!(default_methods(&study), presets);
        assert_eq!(default_reference_method(&study), "best");
        let sky = Scene::load(root.join("assets/scenes/sun_sky.xml")).unwrap();
        let methods = default_methods(&sky);
        assert_eq!(methods[..presets.len()], presets[..]);
        assert_eq!(methods[presets.len()..], ["nee+env+env-uniform", "nee+env", "mis+env+env-uniform", "mis+env", "mis+env+env-compensated"]);
        // Every one is a method the study keeps (compensated only with MIS).
        assert!(methods.iter().all(|m| sky.why_left_out(&crate::method::Method::from_name(m).unwrap()).is_none()), "{methods:?}");
        assert_eq!(default_reference_method(&sky), "best+env");
    }
}
