//! Lamps that are neither axis-aligned nor flat, against Mitsuba 3.9.1 and against each other:
//! assets/scenes/lamps.xml has a flat quad light tilted by 26.6 degrees and two emissive
//! icospheres with smooth shading, one with the vertex normals recomputed for an OBJ without
//! them (Mitsuba's rule, one-sided diffuse), one with its normals given as `vn` (two-sided
//! diffuse), over a diffuse floor; the camera sees both spheres' silhouettes, where shading and
//! geometric normal disagree about the side. The fixture (tests/fixtures/lamps/: 64x48,
//! max_depth 3, box filter, independent sampler, 65536 spp in 64 passes, with the per-pixel
//! variance of its mean) is Mitsuba loading the same file (scripts/lamps_reference.sh).
//!
//! Every unbiased preset, and `nee` and `mis` with the other light selections and triangle
//! samplings, is z-tested against the fixture channel by channel on blocks, as in
//! tests/cornell_box.rs (Šidák-corrected over channels and renders at alpha = 0.01, at least
//! 99.75% of channels passing; the `mis` render scaled by 1.05 must be rejected). Then every
//! method against every other: the image means per channel (Šidák over all pairs and
//! channels at alpha = 0.01) and 8x8 blocks (as above, over all pairs), so that a method that
//! changes the expectation fails even where Mitsuba's noise would hide it.

use crate::common;

use common::*;
use pathlab::film::Film;
use pathlab::method::{LightSampling, Method, Preset, TriangleSampling};
use pathlab::scene::Scene;
use pathlab::stats::{image_mean_and_error, sidak, z_test, z_threshold};

/// The scene at the reference's size and `max_depth`, named relative to the crate (the working
/// directory of `cargo test`), as a user names it: the meshes are found beside the XML file.
fn lamps(reference: &Film, max_depth: u32) -> Scene {
    let defines = [
        ("resx".to_string(), reference.width.to_string()),
        ("resy".to_string(), reference.height.to_string()),
        ("max_depth".to_string(), max_depth.to_string()),
    ];
    Scene::load_with("assets/scenes/lamps.xml", &defines).unwrap()
}

/// Every unbiased preset (light selection `power`, the default for emissive meshes), and the
/// ones that sample lights with the other triangle sampling. Not `all` (642 shadow rays a
/// vertex) nor `uniform` (the quad's two triangles chosen 2 times in 642): both are held to the
/// exact answer in tests/polygon_lights.rs.
fn methods() -> Vec<Method> {
    let mut methods: Vec<Method> = Preset::ALL.iter().map(|p| p.method()).collect();
    for p in [Preset::Nee, Preset::Mis] {
        methods.push(Method { triangles: TriangleSampling::SolidAngle, ..p.method() });
    }
    methods.push(Method { lights: LightSampling::MisBalance, ..Preset::Mis.method() });
    methods
}

/// 4x4 blocks of 256 spp for the methods that sample lights; 8x8 blocks of 1024 spp for those
/// that find lights only by chance (on the few pixels where the camera sees the floor past the
/// quad's edge, 4x4 blocks of 1024 spp of `plain` hold samples that found no light at all, and
/// a variance of 0).
fn plan(method: &Method) -> (u64, u32) {
    if method.lights == LightSampling::None { (1024, 8) } else { (256, 4) }
}

/// Every pair of renders' image means, channel by channel: |z| of their difference within the
/// Šidák threshold for alpha = 0.01 over all pairs and channels. The report and the failures.
fn image_means_agree(methods: &[Method], films: &[Film]) -> (Vec<String>, Vec<String>) {
    let threshold = z_threshold(0.01, 3 * methods.len() * (methods.len() - 1) / 2);
    let (mut report, mut failed) = (Vec::new(), Vec::new());
    for a in 0..methods.len() {
        for b in a + 1..methods.len() {
            for c in 0..3 {
                let ((ma, ea), (mb, eb)) = (image_mean_and_error(&films[a], c), image_mean_and_error(&films[b], c));
                let z = (ma - mb) / (ea * ea + eb * eb).sqrt();
                let line = format!("{} {ma:.5} vs {} {mb:.5}, channel {c}: z {z:+.2} (|z| <= {threshold:.2})", methods[a].name(), methods[b].name());
                if !(z.abs() <= threshold) {
                    failed.push(line.clone());
                }
                report.push(line);
            }
        }
    }
    (report, failed)
}

#[test]
fn the_meshes_of_an_xml_file_named_by_a_relative_path_are_found_beside_it() {
    let scene = Scene::load("assets/scenes/lamps.xml").unwrap();
    assert_eq!(scene.num_triangles(), 2 + 80 + 320 + 2);
    // Recomputed (icosphere.obj has none) and given normals; none for the flat quad and the floor.
    let with_normals: Vec<(&str, bool)> = scene.meshes.iter().map(|m| (m.source.rsplit('/').next().unwrap(), !m.normals.is_empty())).collect();
    assert_eq!(with_normals, [("tilted_quad.obj", false), ("icosphere.obj", true), ("icosphere_vn.obj", true), ("rectangles[0]", false)]);
}

/// Camera rays alone (`max_depth` 1; tests/fixtures/lamps_depth1: 65536 spp in 16 passes), pixel
/// by pixel: a smooth lamp emits on the side of its interpolated normal, as Mitsuba decides in
/// the shading frame, so near its silhouette faces whose winding faces the camera may emit
/// nothing (judged by their winding normals instead, 27 of the 363 edge channels fail, and 3
/// channels Mitsuba shows black).
/// Pixels the reference shows without noise (inside a lamp, or none) must equal it to 1e-4
/// relative: Mitsuba's RGB emitters give back the file's radiance to 4e-5 (0.9 as 0.8999662,
/// 0.4 as 0.4000154). The others, the lamps' edges, are z-tested at alpha = 0.01 Šidák-corrected
/// over their channels, and the render scaled by 1.05 must fail there. An edge pixel is a
/// Bernoulli trial per sample (lit or not), which 1024 samples may never see fail where the
/// reference's 65536 did: the test's variance is taken as at least the reference's per-sample
/// variance at the test's sample count (the same distribution, under the hypothesis tested).
#[test]
fn camera_rays_see_smooth_lamps_emit_on_the_side_of_their_shading_normals_as_mitsuba() {
    let reference = mitsuba_fixture("lamps_depth1");
    let scene = lamps(&reference, 1);
    let film = render(&scene, Preset::Mis.method(), 1024, 600);
    let channels = |f: &Film| f.mean.iter().zip(&f.variance).flat_map(|(m, v)| (0..3).map(move |c| (m[c] as f64, v[c] as f64))).collect::<Vec<_>>();
    let (r, t) = (channels(&reference), channels(&film));
    let edges: Vec<usize> = (0..r.len()).filter(|&i| r[i].1 > 0.0).collect();
    assert!(edges.len() > 100, "{} edge channels", edges.len());
    let threshold = z_threshold(0.01, edges.len());
    let per_sample = reference.spp as f64 / film.spp as f64;
    let failures = |scale: f64| {
        edges
            .iter()
            .filter(|&&i| {
                let var = (scale * scale * t[i].1).max(r[i].1 * per_sample) + r[i].1;
                !((scale * t[i].0 - r[i].0).abs() <= threshold * var.sqrt())
            })
            .count()
    };
    let constant: Vec<String> = (0..r.len())
        .filter(|&i| r[i].1 == 0.0 && !((t[i].0 - r[i].0).abs() <= 1e-4 * r[i].0.abs()))
        .map(|i| format!("pixel {} channel {}: {} where Mitsuba shows {} without noise", i / 3, i % 3, t[i].0, r[i].0))
        .collect();
    let (fail, fail_scaled) = (failures(1.0), failures(1.05));
    println!("{} edge channels, |z| <= {threshold:.2}: {fail} fail; scaled by 1.05: {fail_scaled} fail", edges.len());
    assert!(constant.is_empty() && fail == 0, "{fail} edge channels and {} noise-free ones disagree with Mitsuba:\n{}", constant.len(), constant.join("\n"));
    assert!(fail_scaled > 0, "a 5% bias passes");
}

#[test]
fn every_method_agrees_with_mitsuba_and_with_every_other_on_tilted_and_smooth_lamps() {
    let reference = mitsuba_fixture("lamps");
    let scene = lamps(&reference, 3);
    let methods = methods();
    let films = agrees_with_reference(&reference, &scene, &methods, plan, 700, Preset::Mis.method());

    // Every method against every other, on the image means and on 8x8 blocks.
    let (mut report, mut failed) = image_means_agree(&methods, &films);
    let alpha = sidak(0.01, methods.len() * (methods.len() - 1) / 2);
    for a in 0..methods.len() {
        for b in a + 1..methods.len() {
            let pair = format!("{} vs {}", methods[a].name(), methods[b].name());
            let blocks = z_test(&films[a].downsample(8), &films[b].downsample(8), alpha);
            report.push(format!("{pair}: 8x8 blocks {:.4} of {} channels pass, mean z {:+.3}", blocks.pass_fraction, blocks.channels, blocks.mean_z));
            if blocks.pass_fraction < 0.9975 {
                failed.push(format!("{pair}: 8x8 blocks, {:.4} of channels pass", blocks.pass_fraction));
            }
        }
    }
    println!("{}", report.join("\n"));
    assert!(failed.is_empty(), "methods disagree with each other:\n{}", failed.join("\n"));
}

/// A quad lamp whose vertex normals splay outwards by 50 degrees, over a diffuse floor at
/// `max_depth` 2: from most of the floor, part of the quad faces it by its winding but not by
/// its interpolated normal, and emits nothing there. Next event estimation decides the side of
/// the sampled point as a BSDF-sampled ray decides the side of the point it hits, so the methods
/// that find the lamp only by light sampling (`nee`, both triangle samplings) and those that
/// find it only by BSDF sampling (`cosine`, `phong`) have the same expectation, and MIS too:
/// image means per channel agree pairwise within the Šidák threshold for alpha = 0.01 over all
/// pairs and channels. (Deciding NEE's side by the winding instead makes `nee`, `mis` and
/// `best` 7% brighter than `cosine`: z -41 to -45.)
#[test]
fn light_and_bsdf_sampling_see_the_same_emitting_side_on_a_lamp_with_splayed_normals() {
    let c = 50f64.to_radians().tan();
    let mut obj = String::from("v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n");
    for (x, z) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        obj.push_str(&format!("vn {} -1 {}\n", x * c, z * c));
    }
    obj.push_str("f 1//1 2//2 3//3\nf 1//1 3//3 4//4\n");
    let text = "[camera]\nposition = [0, 2.5, 3]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 40\n\
                [render]\nwidth = 64\nheight = 48\nmax_depth = 2\n\
                [materials.floor]\ndiffuse = 0.5\n[materials.lamp]\ndiffuse = 0.3\nemission = [10, 6, 3]\n\
                [[rectangles]]\nmaterial = \"floor\"\ntransform = { scale = 5, rotate = { axis = [1, 0, 0], angle = -90 } }\n\
                [[meshes]]\nfile = \"lamp.obj\"\nmaterial = \"lamp\"\ntransform = { scale = 0.4, translate = [0.2, 0.6, -0.3] }\n";
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("lamp.obj"), obj).unwrap();
    std::fs::write(dir.path().join("scene.toml"), text).unwrap();
    let scene = Scene::load(dir.path().join("scene.toml")).unwrap();
    assert!(pathlab::gpu::SceneFeatures::of(&scene).has_shading_normals);
    let methods = [
        (Preset::Cosine.method(), 4096),
        (Preset::Phong.method(), 4096),
        (Preset::Nee.method(), 256),
        (Method { triangles: TriangleSampling::SolidAngle, ..Preset::Nee.method() }, 256),
        (Preset::Mis.method(), 256),
        (Preset::Best.method(), 256),
    ];
    let films: Vec<Film> = methods.iter().enumerate().map(|(k, (m, spp))| render(&scene, *m, *spp, 300 + k as u32)).collect();
    let (report, failed) = image_means_agree(&methods.map(|(m, _)| m), &films);
    println!("{}", report.join("\n"));
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}
