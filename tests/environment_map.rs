//! The environment map (Mitsuba's `envmap`, `scene::EnvironmentMap`,
//! `shaders/emitters/environment.wgsl`):
//!
//! 1. pathlab's radiance lookup (`EnvironmentMap::radiance`: the rotation, the direction-to-uv
//!    mapping, the bilinear filter with a periodic longitude and clamped poles, the scale)
//!    against Mitsuba 3.9.1's own envmap evaluated towards 304 directions, the poles and the
//!    seam among them (tests/fixtures/envmap/envmap_evals.json, scripts/envmap_image.py).
//! 2. The kernel's lookup (`environment_map_radiance`) against the host's at the same
//!    directions.
//! 3. Two spheres on a floor under the map (tests/fixtures/envmap/envmap.xml), rendered by `mis`
//!    (escaped rays alone find the map), `mis+env` (next event estimation samples it by
//!    luminance), `mis+env+env-uniform` (uniformly) and `mis+env+env-compensated` (by the
//!    MIS-compensated luminance, Karlík et al. 2019), z-tested against
//!    Mitsuba rendering the same file (64x64, 65536 spp in 64 passes with the per-pixel
//!    variance of its mean; scripts/envmap_reference.sh), on blocks as tests/cornell_box.rs does
//!    (at least 99.75% of channels passing; `mis` scaled by 1.05 is rejected): fails falsely
//!    with probability below 0.01.
//! 4. TOML and XML maps are read; bad ones are refused naming the field or line and column.

use crate::common;

use common::*;
use pathlab::method::{EnvSampling, Method, Preset};
use pathlab::scene::{EnvDistribution, EnvironmentMap, Scene, SceneError};
use pathlab::shaders;

fn fixture(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/envmap").join(name)
}

/// The map of envmap.xml and Mitsuba's values towards the fixture's directions.
fn mitsuba_evals() -> (EnvironmentMap, Vec<[f32; 3]>, Vec<[f32; 3]>) {
    let scene = Scene::load(fixture("envmap.xml")).unwrap();
    let map = scene.environment_map.clone().expect("envmap.xml has a map");
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(fixture("envmap_evals.json")).unwrap()).unwrap();
    let triple = |v: &serde_json::Value| [v[0].as_f64().unwrap() as f32, v[1].as_f64().unwrap() as f32, v[2].as_f64().unwrap() as f32];
    let dirs = json["directions"].as_array().unwrap().iter().map(triple).collect();
    let rgb = json["rgb"].as_array().unwrap().iter().map(triple).collect();
    (map, dirs, rgb)
}

#[test]
fn the_maps_radiance_is_mitsubas() {
    let (map, dirs, expected) = mitsuba_evals();
    assert!(dirs.len() >= 300);
    for (d, e) in dirs.iter().zip(&expected) {
        // At the poles themselves u is undefined: Mitsuba's atan2 of two signed zeros picks
        // one (the fixture's sky varies along its top row; a real sky does not).
        if d[1].abs() > 1.0 - 1e-6 {
            continue;
        }
        let got = map.radiance(*d);
        // f32 rounding of the angles: a texel position off by ~1e-5 times the steepest texel
        // step of the sky (the sun's edge is not steep at these directions' spacing).
        assert!((0..3).all(|c| (got[c] - e[c]).abs() <= 1e-3 * (1.0 + e[c].abs())), "towards {d:?}: pathlab {got:?}, Mitsuba {e:?}");
    }
}

const LOOKUP_KERNEL: &str = r#"
@group(0) @binding(0) var<storage, read> test_dirs: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> test_out: array<vec4f>;

@compute @workgroup_size(64)
fn lookup_main(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x;
    if (i >= arrayLength(&test_dirs)) {
        return;
    }
    test_out[i] = vec4f(environment_map_radiance(test_dirs[i].xyz), 0.0);
}
"#;

#[test]
fn the_kernels_lookup_is_the_hosts() {
    let (map, dirs, _) = mitsuba_evals();
    let queries: Vec<[f32; 4]> = dirs.iter().map(|d| [d[0], d[1], d[2], 0.0]).collect();
    // The emitters' files need the scene's and the emitter table's: the path tracer's whole module.
    let inputs = vec![(0, bytemuck::cast_slice(&queries).to_vec()), (shaders::bindings::ENVIRONMENT_MAP.number, bytemuck::cast_slice(&map.pack()).to_vec())];
    let out = run_test_kernel(&shaders::PATH_TRACER, LOOKUP_KERNEL, "lookup_main", inputs, queries.len(), 1);
    for (d, got) in dirs.iter().zip(&out) {
        if d[1].abs() > 1.0 - 1e-6 {
            continue; // the poles: u undefined (see above)
        }
        let e = map.radiance(*d);
        // lavapipe's atan2 and acos are less exact than the host's: at the sun's edge (a step
        // of 50x over one texel) a direction off by ~1e-4 rad moves the value by 0.2%.
        assert!((0..3).all(|c| (got[c] - e[c]).abs() <= 5e-3 * (1.0 + e[c].abs())), "towards {d:?}: kernel {:?}, host {e:?}", &got[..3]);
    }
}

#[test]
fn mis_agrees_with_mitsuba_under_an_environment_map() {
    let reference = mitsuba_fixture("envmap");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(fixture("envmap.xml"), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let methods: Vec<Method> = ["mis", "mis+env", "mis+env+env-uniform", "mis+env+env-compensated"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (1024, 2), 1700, Preset::Mis.method());
}

#[test]
fn maps_are_read_from_toml_and_xml_and_bad_ones_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(fixture("sky.exr"), dir.path().join("sky.exr")).unwrap();
    let toml = |extra: &str| {
        format!(
            "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 40\n[render]\nwidth = 8\nheight = 8\nmax_depth = 3\n{extra}\n\
             [materials.m]\ndiffuse = 0.5\n[[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n"
        )
    };
    let path = dir.path().join("t.toml");
    let load = |extra: &str| {
        std::fs::write(&path, toml(extra)).unwrap();
        Scene::load(&path)
    };
    let s = load("[environment_map]\nfilename = \"sky.exr\"\nscale = 2\ntransform = { rotate = { axis = [0, 1, 0], angle = 90 } }").unwrap();
    let m = s.environment_map.as_ref().unwrap();
    assert_eq!((m.image.width, m.image.height, m.scale), (64, 32, 2.0));
    assert!((m.to_world[0][2] - 1.0).abs() < 1e-12, "rotation about y by 90 degrees: {:?}", m.to_world);
    assert!(s.has_environment());
    // A translation moves no direction at infinity: accepted, without effect (as in Mitsuba).
    let moved = load("[environment_map]\nfilename = \"sky.exr\"\nscale = 2\ntransform = { rotate = { axis = [0, 1, 0], angle = 90 }, translate = [0, 8.87, 0] }").unwrap();
    assert_eq!(moved.environment_map.as_ref().unwrap().to_world, m.to_world);
    let hash = s.content_hash();
    assert_ne!(hash, load("[environment_map]\nfilename = \"sky.exr\"\nscale = 3").unwrap().content_hash(), "the scale is part of the scene");
    for (extra, field, message) in [
        ("[environment_map]\nfilename = \"cloudy.exr\"", "environment_map.filename", "image file \"cloudy.exr\" not found (searched"),
        ("[environment_map]\nfilename = \"sky.exr\"\nscale = -1", "environment_map.scale", "scale must be >= 0"),
        ("[environment_map]\nfilename = \"sky.exr\"\ntransform = { scale = 2 }", "environment_map.transform", "must be a rotation"),
        ("environment = 1\n[environment_map]\nfilename = \"sky.exr\"", "render.environment", "not both"),
    ] {
        let extra = if extra.starts_with("environment = 1") { extra.replacen("environment = 1\n", "", 1) } else { extra.to_string() };
        let text = if field == "render.environment" { toml(&extra).replace("max_depth = 3\n", "max_depth = 3\nenvironment = 1\n") } else { toml(&extra) };
        std::fs::write(&path, text).unwrap();
        match Scene::load(&path) {
            Err(SceneError::Invalid(d)) => assert!(d.iter().any(|d| d.field == field && d.message.contains(message) && d.line >= 1), "{extra}: {d:?}"),
            other => panic!("{extra}: accepted ({:?})", other.map(|s| s.environment_map.is_some())),
        }
    }

    // XML: the file found by Mitsuba's resolver; a second infinite emitter refused.
    let xml_path = dir.path().join("t.xml");
    let xml = |emitters: &str| {
        format!(
            "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/><film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/><integer name=\"height\" value=\"8\"/><rfilter type=\"box\"/></film></sensor>\n\
             {emitters}\n<shape type=\"sphere\"><point name=\"center\" x=\"0\" y=\"0\" z=\"3\"/></shape>\n</scene>\n"
        )
    };
    std::fs::write(&xml_path, xml("<emitter type=\"envmap\"><string name=\"filename\" value=\"sky.exr\"/><float name=\"scale\" value=\"0.5\"/></emitter>")).unwrap();
    let s = Scene::load(&xml_path).unwrap();
    assert_eq!(s.environment_map.as_ref().map(|m| (m.file.clone(), m.scale)), Some((dir.path().join("sky.exr"), 0.5)));
    for (emitters, message) in [
        ("<emitter type=\"envmap\"><string name=\"filename\" value=\"cloudy.hdr\"/></emitter>", "image file \"cloudy.hdr\" not found (searched"),
        ("<emitter type=\"envmap\"/>", "needs <string name=\"filename\">"),
        ("<emitter type=\"envmap\"><string name=\"filename\" value=\"sky.exr\"/></emitter>\n<emitter type=\"constant\"/>", "a second infinite emitter"),
    ] {
        std::fs::write(&xml_path, xml(emitters)).unwrap();
        let e = Scene::load(&xml_path).unwrap_err().to_string();
        assert!(e.contains("t.xml:3:") || e.contains("t.xml:4:"), "{emitters}: {e}");
        assert!(e.contains(message), "{emitters}: {e}");
    }
}

const SAMPLING_KERNEL: &str = r#"
@group(0) @binding(0) var<storage, read> test_u: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> test_out: array<vec4f>;

// Per input: a direction drawn by the luminance distribution with its reported density, and
// the pdf function at that direction and at a uniformly drawn one.
@compute @workgroup_size(64)
fn sampling_main(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x;
    if (i >= arrayLength(&test_u)) {
        return;
    }
    let s = sample_environment_map(test_u[i].xy);
    let uniform = square_to_uniform_sphere(test_u[i].zw);
    test_out[2u * i] = s;
    test_out[2u * i + 1u] = vec4f(pdf_environment_map(s.xyz), pdf_environment_map(uniform), 0.0, 0.0);
}
"#;

/// A map for the sampling tests: a fixture image, or a constant one.
fn test_map(file: Option<&str>, to_world: [[f64; 3]; 3]) -> EnvironmentMap {
    use pathlab::scene::image_file::{read_image, Image, Texels};
    let image = match file {
        Some(f) => read_image(&fixture(f), false).unwrap(),
        None => Image { width: 16, height: 8, texels: Texels::Float(vec![[0.5; 3]; 128]), srgb: false },
    };
    EnvironmentMap { file: file.unwrap_or("constant").into(), content_hash: image.content_hash(), image: std::sync::Arc::new(image), scale: 1.0, to_world }
}

/// Draws `n` directions by the map's `distribution` in the kernel; returns the
/// chi-square p-value of their counts in the map's own cells, each split in 2 x 2 (the
/// distribution is constant over a cell of the uv square: expected counts exact), the
/// fraction of samples whose reported density differs from the pdf function or that lie in a
/// cell of zero probability, and the
/// estimate 4 pi mean(pdf) of the pdf's integral over the sphere from uniform directions, with
/// its standard error.
fn sampling_check(map: &EnvironmentMap, distribution: EnvDistribution, n: usize, seed: u64) -> (f64, f64, (f64, f64)) {
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        ((state >> 40) as f32) / (1u64 << 24) as f32
    };
    let u: Vec<[f32; 4]> = (0..n).map(|_| [next(), next(), next(), next()]).collect();
    let inputs = vec![(0, bytemuck::cast_slice(&u).to_vec()), (shaders::bindings::ENVIRONMENT_MAP.number, bytemuck::cast_slice(&map.pack()).to_vec())];
    let strategy = match distribution {
        EnvDistribution::Luminance => EnvSampling::Luminance,
        EnvDistribution::Compensated => EnvSampling::Compensated,
    };
    let source = shaders::assemble(&shaders::PATH_TRACER, SAMPLING_KERNEL);
    let run = pathlab::gpu::KernelRun {
        source: &source,
        entry: "sampling_main",
        constants: &[("ENV_SAMPLING", strategy.constant() as f64)],
        inputs,
        uniforms: vec![],
        texel_tables: vec![],
        output: (1, (n * 2 * 16) as u64),
        workgroups: (n as u32).div_ceil(64),
    };
    let out: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&run.run(gpu()).expect("sampling kernel"));
    let (w, h) = (map.image.width as usize, map.image.height as usize);
    let (density, _, _) = map.sampling_tables(distribution);
    let r = map.to_world;
    let mut observed = vec![0u64; 4 * w * h];
    let (mut mismatches, mut sum, mut sum2) = (0usize, 0.0f64, 0.0f64);
    for pair in out.chunks(2) {
        let (d, p) = (pair[0], pair[1]);
        assert!(d.iter().all(|x| x.is_finite()) && d[3] > 0.0, "sample {d:?}");
        let d = [d[0] as f64, d[1] as f64, d[2] as f64, d[3] as f64];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        assert!((len - 1.0).abs() < 1e-5, "direction of length {len}");
        // The map's (u, t) in f64: v = R^T d.
        let v: Vec<f64> = (0..3).map(|c| r[0][c] * d[0] + r[1][c] * d[1] + r[2][c] * d[2]).collect();
        let u = (v[0].atan2(-v[2]) / (2.0 * std::f64::consts::PI)).rem_euclid(1.0);
        let t = v[1].clamp(-1.0, 1.0).acos() / std::f64::consts::PI;
        let (x, y) = (((u * w as f64) as usize).min(w - 1), ((t * h as f64) as usize).min(h - 1));
        let sx = (((u * w as f64 - x as f64) * 2.0) as usize).min(1);
        let sy = (((t * h as f64 - y as f64) * 2.0) as usize).min(1);
        observed[(2 * y + sy) * 2 * w + 2 * x + sx] += 1;
        if (d[3] - p[0] as f64).abs() > 1e-4 * d[3] {
            mismatches += 1;
        }
        let q = 4.0 * std::f64::consts::PI * p[1] as f64;
        sum += q;
        sum2 += q * q;
    }
    // Expected: the cell's share of the uv square's density, a quarter per sub-cell; bins with
    // fewer than 5 expected pooled into one.
    // Samples in cells of zero probability are counted apart (the pooled bins would hide
    // them): only rounding at a cell's edge may put one there.
    let mut in_zero = 0u64;
    let mut chi2 = 0.0;
    let mut bins = 0usize;
    let (mut pooled_e, mut pooled_o) = (0.0, 0u64);
    for (b, &o) in observed.iter().enumerate() {
        let (y, x) = (b / (2 * w) / 2, (b % (2 * w)) / 2);
        let e = n as f64 * density[y * w + x] / (w * h) as f64 / 4.0;
        if e == 0.0 {
            in_zero += o;
            continue;
        }
        if e < 5.0 {
            pooled_e += e;
            pooled_o += o;
            continue;
        }
        chi2 += (o as f64 - e).powi(2) / e;
        bins += 1;
    }
    if pooled_e > 0.0 {
        chi2 += (pooled_o as f64 - pooled_e).powi(2) / pooled_e.max(1e-9);
        bins += 1;
    }
    let mean = sum / n as f64;
    let error = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
    (pathlab::stats::chi2_sf(chi2, bins - 1), (mismatches as u64 + in_zero) as f64 / n as f64, (mean, error))
}

#[test]
fn luminance_and_compensated_sampling_fit_their_distributions_and_their_pdfs_integrate_to_one() {
    // A sky with a sun of 2 x 2 texels at 10^4 times its brightness (sun.exr), the same turned
    // about x, a gentler sky (sky.exr) and a constant map (whose compensated distribution is
    // uniform over the sphere), each by both distributions. Chi-square at 0.01 per case,
    // Šidák-corrected: a false failure has probability below 0.01 over all eight. The pdf's
    // integral: within 6 standard errors of 1 (false failure ~1e-9 per case).
    let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let (c, s) = (0.6f64.cos(), 0.6f64.sin());
    let turned = [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]];
    let maps = [("sun", test_map(Some("sun.exr"), identity)), ("sun turned", test_map(Some("sun.exr"), turned)), ("sky", test_map(Some("sky.exr"), identity)), ("constant", test_map(None, turned))];
    let distributions = [EnvDistribution::Luminance, EnvDistribution::Compensated];
    let level = pathlab::stats::sidak(0.01, maps.len() * distributions.len());
    let mut report = Vec::new();
    let mut failed = Vec::new();
    for (k, (name, map)) in maps.iter().enumerate() {
        for (j, distribution) in distributions.into_iter().enumerate() {
            let (p, mismatches, (integral, error)) = sampling_check(map, distribution, 1 << 20, 17 + k as u64 + 100 * j as u64);
            report.push(format!(
                "{name}, {distribution:?}: chi-square p = {p:.4}, reported pdf off the pdf function in {:.1e} of samples, integral of the pdf {integral:.5} +- {error:.5}",
                mismatches
            ));
            // Samples within rounding of a cell's edge may be found in the neighbour cell.
            if p < level || mismatches > 1e-4 || (integral - 1.0).abs() > 6.0 * error {
                failed.push(format!("{name}, {distribution:?}"));
            }
        }
    }
    println!("{}", report.join("\n"));
    assert!(failed.is_empty(), "{failed:?}:\n{}", report.join("\n"));
}

#[test]
fn the_compensated_distribution_is_the_luminance_less_its_mean_where_positive() {
    // The sun map: the compensated density is zero exactly where a cell's luminance bound is at
    // most the bounds' mean over the sphere, and elsewhere proportional to the excess.
    let map = test_map(Some("sun.exr"), [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    let (lum, _, _) = map.sampling_tables(EnvDistribution::Luminance);
    let (comp, _, _) = map.sampling_tables(EnvDistribution::Compensated);
    let (w, h) = (map.image.width as usize, map.image.height as usize);
    let sin = |y: usize| (std::f64::consts::PI * (y as f64 + 0.5) / h as f64).sin();
    // Luminance density ∝ L sin; recover L up to a factor, then its solid-angle mean.
    let (mut sum, mut omega) = (0.0, 0.0);
    for y in 0..h {
        for x in 0..w {
            sum += lum[y * w + x];
            omega += sin(y);
        }
    }
    let mean = sum / omega;
    let excess: Vec<f64> = (0..h * w).map(|i| (lum[i] / sin(i / w) - mean).max(0.0) * sin(i / w)).collect();
    let total: f64 = excess.iter().sum();
    let zero = comp.iter().filter(|&&c| c == 0.0).count();
    assert!(zero > 0 && zero < w * h, "{zero} of {} cells left to BSDF sampling", w * h);
    for i in 0..w * h {
        let expected = excess[i] / total * (w * h) as f64;
        assert!((comp[i] - expected).abs() <= 1e-9 * (1.0 + expected), "cell {i}: {} against {expected}", comp[i]);
    }
}

#[test]
fn compensated_sampling_is_refused_without_mis() {
    let scene = Scene::load(fixture("envmap.xml")).unwrap();
    for name in ["nee+env+env-compensated", "independent/cosine/nee+env+env-compensated"] {
        let method = Method::from_name(name).unwrap();
        let err = pathlab::render::RenderError::check_sees_lights(&scene, &method).unwrap_err().to_string();
        assert!(err.contains("compensated") && err.contains("mis"), "{err}");
        assert!(scene.why_left_out(&method).is_some_and(|why| why.contains("compensated")));
    }
    for name in ["mis+env+env-compensated", "mis-balance+env+env-compensated", "nee+env", "mis+env-compensated"] {
        let method = Method::from_name(name).unwrap();
        assert!(pathlab::render::RenderError::check_sees_lights(&scene, &method).is_ok(), "{name}");
        assert!(scene.why_left_out(&method).is_none(), "{name}");
    }
}

#[test]
fn a_black_map_is_not_a_light_and_is_never_importance_sampled() {
    let mut map = test_map(None, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    map.image = std::sync::Arc::new(pathlab::scene::image_file::Image { width: 4, height: 2, texels: pathlab::scene::image_file::Texels::Float(vec![[0.0; 3]; 8]), srgb: false });
    assert!(map.is_black());
    assert!(map.sampling_tables(EnvDistribution::Luminance).0.is_empty());
    assert!(map.sampling_tables(EnvDistribution::Compensated).0.is_empty());
    let packed = map.pack();
    assert_eq!((packed[12], packed[13]), (0.0, 0.0), "the record says: not importance-sampled (uniform directions instead)");
}

/// `render` without `--method` under an environment map samples the map (`best+env`, as
/// Mitsuba's `path` samples its `envmap`), and without one renders `best`.
#[test]
fn the_default_method_samples_an_environment_map() {
    let dir = tempfile::tempdir().unwrap();
    for (scene, expected) in [(fixture("envmap.xml"), "method best+env "), (std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.toml"), "method best ")] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_pathlab"))
            .arg("render")
            .arg(&scene)
            .args(["--width", "8", "--height", "4", "--spp", "4", "-o"])
            .arg(dir.path().join("out.exr"))
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success() && text.contains(expected), "{}: {text}", scene.display());
    }
}
