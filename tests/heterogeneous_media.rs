//! Heterogeneous media and grid albedos (`scene::media`, `Field::Grid`; shaders/medium.wgsl's
//! delta and ratio tracking): Mitsuba's `heterogeneous` medium under its `volpath` integrator.
//!
//! 1. Exact: an absorbing unit sphere behind a `null` boundary, its σ_t a 3-channel grid (x 4)
//!    whose box covers only part of the sphere (the medium is empty outside it; camera rays enter
//!    the box inside the sphere),
//!    in front of a white environment, transmits exp(-∫σ_t) per channel: the optical depth of
//!    each ray integrated by the midpoint rule (400 steps) through the grid's host twin
//!    (`GridVolume::eval`), each pixel the mean over a 12 x 12 grid of its points. `plain` and
//!    `mis` (delta tracking) are z-tested against it on 2x2 blocks, Šidák-corrected (false
//!    failure below 0.01), and by the whole image's mean per channel (|z| <= 4.5), which
//!    rejects the exact image of σ_t x 1.05.
//! 2. Exact: a furnace: the same grid with albedo 1, forward-scattering (g = 0.5), in a white
//!    environment is white whatever the scattering: `plain` (delta tracking alone), and next
//!    event estimation from points in the medium (`nee+env`, `mis+env`: shadow rays by ratio
//!    tracking), z-tested against 1 on 4x4 blocks at 512 spp; albedo 0.95 is rejected.
//! 3. Against Mitsuba 3.9.1: tests/fixtures/hetero_media/hetero.xml (a heterogeneous medium of
//!    RGB grid extinction and grey grid albedo partly covering its `null` sphere, a homogeneous
//!    medium of grid albedo behind a thin dielectric, a heterogeneous medium of constant
//!    extinction bounded by its constvolume's box; a floor, an area light and a point light),
//!    rendered by `mis` and `nee` and z-tested against Mitsuba's volpath on the same file (64x48,
//!    65536 spp in 64 passes with the variance of the mean: WIDTH=64 HEIGHT=48
//!    scripts/xml_fixture_reference.sh tests/fixtures/hetero_media/hetero.xml), as
//!    tests/cornell_box.rs does (at least 99.75% of channels pass, Šidák-corrected; `mis` x 1.05
//!    is rejected).
//! 4. What cannot be read is refused by name and line.
use crate::common;
use crate::media::refusal;
use common::*;
use glam::DVec3;
use pathlab::film::Film;
use pathlab::method::{Method, Preset};
use pathlab::scene::media::Field;
use pathlab::scene::{Scene, SceneError};
use pathlab::stats::{image_mean_and_error, sidak, z_test};

fn fixture(name: &str) -> String {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/hetero_media").join(name).display().to_string()
}

/// A unit sphere at the origin bounding a heterogeneous medium whose σ_t is rgb.vol (x 2) in
/// the box [-1, 0.5] x [-1, 1] x [-1, 0.3] (camera rays enter the sphere outside it and the box
/// inside the sphere), with a null BSDF, seen from z = 4 against a white environment.
fn grid_sphere(extra: &str, size: u32, max_depth: u32) -> String {
    format!(
        "[camera]\nposition = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nup = [0.0, 1.0, 0.0]\nfov_y = 40.0\n\
         [render]\nwidth = {size}\nheight = {size}\nmax_depth = {max_depth}\nenvironment = 1.0\n\
         [media.m]\ntype = \"heterogeneous\"\nscale = 2.0\n\
         sigma_t = {{ texture = \"volume\", filename = \"{}\", to_world = [[1.5, 0.0, 0.0, -1.0], [0.0, 2.0, 0.0, -1.0], [0.0, 0.0, 1.3, -1.0]] }}\n{extra}\n\
         [materials.boundary]\nbsdf = \"thindielectric\"\nint_ior = 1.0\next_ior = 1.0\ninterior = \"m\"\n\
         [[spheres]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = \"boundary\"\n",
        fixture("rgb.vol")
    )
}

/// The exact image of the absorbing sphere: per pixel, the mean over a 12 x 12 grid of its
/// points of exp(-τ), τ the optical depth scale × ∫σ_t along the chord inside the grid's box
/// (midpoint rule, 400 steps; σ_t by the grid's host twin), times `factor`.
fn optical_depth_image(scene: &Scene, size: u32, factor: f64) -> Film {
    let m = &scene.media[0];
    let Field::Grid(grid) = &m.sigma_t else { panic!("a grid") };
    let [lo, hi] = pathlab::scene::media::grid_bounds(grid);
    let half = (20.0f64).to_radians().tan();
    let origin = DVec3::new(0.0, 0.0, 4.0);
    let (n, steps) = (12, 400);
    let mut mean = Vec::new();
    for py in 0..size {
        for px in 0..size {
            let mut sum = DVec3::ZERO;
            for j in 0..n {
                for i in 0..n {
                    let sx = 2.0 * (px as f64 + (i as f64 + 0.5) / n as f64) / size as f64 - 1.0;
                    let sy = 1.0 - 2.0 * (py as f64 + (j as f64 + 0.5) / n as f64) / size as f64;
                    let d = DVec3::new(sx * half, sy * half, -1.0).normalize();
                    // The chord through the unit sphere, [b' - √disc, b' + √disc].
                    let b = -d.dot(origin);
                    let disc = b * b - (origin.length_squared() - 1.0);
                    let mut tau = DVec3::ZERO;
                    if disc > 0.0 {
                        let (t0, t1) = (b - disc.sqrt(), b + disc.sqrt());
                        let h = (t1 - t0) / steps as f64;
                        for s in 0..steps {
                            let p = origin + d * (t0 + (s as f64 + 0.5) * h);
                            if p.cmpge(lo).all() && p.cmple(hi).all() {
                                let v = grid.eval(p.as_vec3().to_array());
                                tau += DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64) * h;
                            }
                        }
                    }
                    let tau = tau * m.scale * factor;
                    sum += DVec3::new((-tau.x).exp(), (-tau.y).exp(), (-tau.z).exp());
                }
            }
            let m = sum / (n * n) as f64;
            mean.push([m.x as f32, m.y as f32, m.z as f32]);
        }
    }
    Film { width: size, height: size, spp: u64::MAX, mean, variance: vec![[0.0; 3]; (size * size) as usize] }
}

#[test]
fn an_absorbing_grid_transmits_its_optical_depth() {
    const MIN_PASS: f64 = 0.9975;
    let scene = Scene::parse(&grid_sphere("albedo = 0.0", 32, 4).replace("scale = 2.0", "scale = 4.0"), "absorb.toml").unwrap();
    assert!(scene.media[0].is_heterogeneous());
    let exact = optical_depth_image(&scene, 32, 1.0);
    let methods = [Preset::Plain.method(), Preset::Mis.method()];
    let alpha = sidak(0.01, methods.len() + 1);
    // The whole image's mean per channel, z-tested too: |z| <= 4.5 (false failure 4e-5 over
    // the 6 tests).
    let image_z = |exact: &Film, film: &Film| -> [f64; 3] {
        std::array::from_fn(|c| {
            let (m, se) = image_mean_and_error(film, c);
            let e = exact.mean.iter().map(|p| p[c] as f64).sum::<f64>() / exact.mean.len() as f64;
            (m - e) / se
        })
    };
    let mut last = None;
    for (k, method) in methods.iter().enumerate() {
        let film = render(&scene, *method, 1024, 5100 + k as u32);
        let z = z_test(&exact.downsample(2), &film.downsample(2), alpha);
        let whole = image_z(&exact, &film);
        println!("{}: {:.4} of {} pass |z| <= {:.2}, max |z| {:.2}, mean z {:+.3}; image mean z {whole:+.2?}", method.name(), z.pass_fraction, z.channels, z.threshold, z.max_abs_z, z.mean_z);
        assert!(z.pass_fraction >= MIN_PASS, "{} disagrees with the optical depth: {z:?}", method.name());
        assert!(whole.iter().all(|z| z.abs() <= 4.5), "{}: the image's mean disagrees with the optical depth: z {whole:?}", method.name());
        last = Some(film);
    }
    // Power: the exact image of σ_t x 1.05 is rejected by the image's mean (pixel by pixel the
    // difference is within the noise of 1024 samples).
    let wrong = optical_depth_image(&scene, 32, 1.05);
    let whole = image_z(&wrong, last.as_ref().unwrap());
    println!("σ_t x 1.05: image mean z {whole:+.2?}");
    assert!(whole.iter().any(|z| z.abs() > 4.5), "σ_t x 1.05 passes: z {whole:?}");
}

#[test]
fn a_white_heterogeneous_furnace_is_white() {
    let medium = "albedo = 1.0\nphase = \"hg\"\ng = 0.5";
    let scene = Scene::parse(&grid_sphere(medium, 24, 64), "furnace.toml").unwrap();
    let grey = Scene::parse(&grid_sphere(&medium.replace("albedo = 1.0", "albedo = 0.95"), 24, 64), "grey.toml").unwrap();
    // 512 samples: tracking's paths are long (the suite's time).
    crate::media::assert_white_furnace(&scene, &grey, 512, 5110);
}

#[test]
fn heterogeneous_media_agree_with_mitsuba() {
    let reference = mitsuba_fixture("hetero_media");
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/hetero_media/hetero.xml");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(file, &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.media.iter().filter(|m| m.is_heterogeneous()).count(), 2);
    let methods: Vec<Method> = ["mis", "nee"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (1024, 4), 5120, Preset::Mis.method());
}

/// The errors of an XML scene that must be refused, one `line:column: message` each.
fn xml_refusal(xml: &str) -> String {
    match load_xml(xml, "bad.xml") {
        Err(SceneError::Invalid(d)) => d.iter().map(|d| format!("{}:{}: {}", d.line, d.column, d.message)).collect::<Vec<_>>().join("\n"),
        other => panic!("accepted: {other:?}"),
    }
}

#[test]
fn bad_heterogeneous_media_are_refused_by_name_and_line() {
    let base = grid_sphere("albedo = 0.5", 8, 4);
    // A grid in a homogeneous medium, which has one σ_t everywhere.
    let e = refusal(&base.replace("type = \"heterogeneous\"\n", ""));
    assert!(e.contains("media.m.sigma_t") && e.contains("type = \"heterogeneous\" for a grid"), "{e}");
    let e = refusal(&base.replace("type = \"heterogeneous\"", "type = \"cloudy\""));
    assert!(e.contains("media.m.type") && e.contains("unknown medium type \"cloudy\""), "{e}");
    // A grid's box is its to_world's cube, not `bounds`.
    let e = refusal(&base.replace("albedo = 0.5", "albedo = 0.5\nbounds = [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]"));
    assert!(e.contains("media.m.bounds") && e.contains("only with a constant sigma_t"), "{e}");
    // An albedo grid beyond 1, a texture looked up at uvs, a negative scale.
    let e = refusal(&base.replace("scale = 2.0", "scale = -1.0"));
    assert!(e.contains("media.m.scale") && e.contains(">= 0"), "{e}");
    let e = refusal(&base.replace("albedo = 0.5", "albedo = { texture = \"checkerboard\" }"));
    assert!(e.contains("media.m.albedo") && e.contains("give a volume texture, not a checkerboard"), "{e}");
    let scaled = base.replace("albedo = 0.5", &format!("albedo = {{ texture = \"volume\", filename = \"{}\" }}", fixture("rgb.vol")));
    // rgb.vol's cells reach 0.85: a valid albedo; bounds in a constant heterogeneous medium
    // must be ordered.
    Scene::parse(&scaled, "ok.toml").unwrap();
    let constant = base.replace(&base[base.find("sigma_t = {").unwrap()..base.find("albedo").unwrap()], "sigma_t = 1.0\nbounds = [[1.0, 0.0, 0.0], [0.0, 1.0, 1.0]]\n");
    let e = refusal(&constant);
    assert!(e.contains("media.m.bounds") && e.contains("min < max"), "{e}");
    // A medium so dense that tracking alone would pass llvmpipe's loop limit is refused, and
    // the refusal says what to change (a hardware GPU has no such limit).
    let dense = Scene::parse(&grid_sphere("albedo = 0.5", 8, 64).replace("scale = 2.0", "scale = 2000.0"), "dense.toml").unwrap();
    if gpu().info.device_type == wgpu::DeviceType::Cpu {
        match pathlab::render::Renderer::new(gpu(), pipelines(), &dense, Preset::Mis.method(), 1) {
            Err(e) => assert!(e.to_string().contains("null collisions along each path segment and shadow ray: a lower `scale`"), "{e}"),
            Ok(_) => panic!("a medium of majorant 1700 renders on llvmpipe"),
        }
    }
    // XML: a volume plugin pathlab lacks, a volume of another name, a grid in a homogeneous
    // medium, at their lines.
    let xml = std::fs::read_to_string(fixture("hetero.xml")).unwrap().replace("\"rgb.vol\"", &format!("\"{}\"", fixture("rgb.vol"))).replace("\"grey.vol\"", &format!("\"{}\"", fixture("grey.vol")));
    let e = xml_refusal(&xml.replacen("type=\"constvolume\"", "type=\"noisevolume\"", 1));
    assert!(e.contains("<volume type=\"noisevolume\"> is not supported (pathlab has constvolume, gridvolume)"), "{e}");
    let e = xml_refusal(&xml.replacen("<volume name=\"albedo\"", "<volume name=\"density\"", 1));
    assert!(e.contains("a <volume> in a <medium> is its `sigma_t` or `albedo`"), "{e}");
    let e = xml_refusal(&xml.replacen("<medium id=\"cloud\" type=\"heterogeneous\">", "<medium id=\"cloud\" type=\"homogeneous\">", 1));
    assert!(e.contains("needs <medium type=\"heterogeneous\">"), "{e}");
    let e = xml_refusal(&xml.replacen("<medium id=\"cloud\" type=\"heterogeneous\">", "<medium id=\"cloud\" type=\"gridmedium\">", 1));
    assert!(e.contains("<medium type=\"gridmedium\"> is not supported (pathlab has homogeneous and heterogeneous media)"), "{e}");
}

