//! The viewer's render driver without a window (`src/viewer/driver.rs`): frames add samples,
//! the split view alternates between its methods, and saving writes the EXR with the header
//! `pathlab render` writes and a PNG of what is shown.

use crate::common;

use std::time::Duration;

use common::{gpu, study_scene};
use pathlab::display::DisplayTransform;
use pathlab::method::Preset;
use pathlab::output::read_exr;
use pathlab::viewer::driver::{Driver, ViewSettings};
use pathlab::viewer::View;

#[test]
fn frames_add_samples_split_alternates_and_save_writes_exr_and_png() {
    let mut scene = study_scene();
    scene.render.width = 32;
    scene.render.height = 16;
    let methods = [Preset::Mis.method(), Preset::Plain.method()];
    let mut driver = Driver::new(gpu().clone(), scene, &methods, 7, None, Duration::from_millis(20)).unwrap();
    let settings = ViewSettings { view: View::Radiance, display: DisplayTransform::default() };
    for _ in 0..10 {
        driver.frame(settings, false).unwrap();
    }
    gpu().wait_idle().unwrap();
    // Ten frames, alternating: five for each method, at least one sample each.
    for slot in &driver.slots {
        assert!(slot.spp() >= 5, "{} spp", slot.spp());
    }
    // Paused frames add nothing.
    let before: Vec<u64> = driver.slots.iter().map(|s| s.spp()).collect();
    for _ in 0..3 {
        driver.frame(settings, true).unwrap();
    }
    assert_eq!(before, driver.slots.iter().map(|s| s.spp()).collect::<Vec<_>>());

    let dir = crate::common::scratch_dir("viewer-driver");
    let files = driver.save(&dir, View::Radiance).unwrap();
    assert_eq!(files.len(), 4, "{files:?}");
    for (slot, name, seed) in [(0, "mis", "7"), (1, "plain", "8")] {
        let spp = driver.slots[slot].spp();
        let exr = dir.join(format!("study-{name}-{spp}spp.exr"));
        let (film, meta) = read_exr(&exr).unwrap();
        let get = |k: &str| meta.iter().find(|(key, _)| key == k).map(|(_, v)| v.clone()).unwrap_or_default();
        assert_eq!((film.width, film.height, film.spp), (32, 16, spp));
        assert_eq!((get("method"), get("seed"), get("spp")), (name.to_string(), seed.to_string(), spp.to_string()));
        let png = image::open(dir.join(format!("study-{name}-{spp}spp.png"))).unwrap();
        assert_eq!((png.width(), png.height()), (32, 16));
    }
}

/// The viewer's partial passes (a share of the rows per frame, `submit_partial`) give every
/// pixel exactly the samples of whole passes: the accumulators agree bit for bit, across
/// accumulator bands.
#[test]
fn partial_passes_equal_whole_passes_bit_for_bit() {
    use pathlab::render::{Budget, Renderer};
    let mut scene = study_scene();
    scene.render.width = 24;
    scene.render.height = 20;
    let band_bytes = 6 * 24 * std::mem::size_of::<pathlab::film::AccumPixel>() as u64;
    let method = Preset::Best.method();
    let mut whole = Renderer::with_band_bytes(gpu(), common::pipelines(), &scene, method, 3, band_bytes).unwrap();
    whole.render(Budget::Samples(5), &std::sync::atomic::AtomicBool::new(false), |_| {}).unwrap();
    let mut parts = Renderer::with_band_bytes(gpu(), common::pipelines(), &scene, method, 3, band_bytes).unwrap();
    assert!(parts.bands() > 2);
    // Two passes of 2 samples in 7-row steps (crossing band edges), then one whole pass of 1.
    for _ in 0..2 {
        let mut rows = 0;
        while rows < 20 {
            rows += parts.submit_partial(2, 7).unwrap();
            assert_eq!(parts.pass_in_progress(), rows < 20);
        }
    }
    parts.submit(1).unwrap();
    assert_eq!(parts.spp(), 5);
    assert_eq!(whole.accumulators().unwrap(), parts.accumulators().unwrap());
}
