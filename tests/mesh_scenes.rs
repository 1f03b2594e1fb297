//! Scenes with triangle meshes on the GPU: an analytic answer for every method and light
//! option, one-sided emission, the traversal guard on a worst-case scene, and bad mesh input
//! refused with the file, line and field.
//!
//! The analytic scene: the camera inside a closed box whose walls all have albedo a and emit e
//! towards the inside. Every path vertex then collects e, and at `max_depth` d the radiance is
//! L = e (1 - a^d) / (1 - a) exactly, in every pixel. Each render's image mean is z-tested
//! against L (per channel, Šidák-corrected for alpha = 0.01 over all renders and channels of
//! the file), so the file fails falsely with probability below 0.01.

use crate::common;

use common::*;
use pathlab::method::{Method, Preset};
use pathlab::scene::{Scene, SceneError};
use pathlab::stats::{image_mean_and_error, z_threshold};

const ALBEDO: f64 = 0.5;
const EMISSION: f64 = 0.25;
const DEPTH: u32 = 4;

fn expected_radiance() -> f64 {
    EMISSION * (1.0 - ALBEDO.powi(DEPTH as i32)) / (1.0 - ALBEDO)
}

fn box_scene(shape: &str) -> String {
    format!(
        "[camera]\nposition = [0.1, -0.2, 0.3]\nlook_at = [1, 0.5, -2]\nup = [0, 1, 0]\nfov_x = 100\n\
         [render]\nwidth = 16\nheight = 16\nmax_depth = {DEPTH}\n\
         [materials.wall]\ndiffuse = {ALBEDO}\nemission = {EMISSION}\n{shape}"
    )
}

/// Writes `files` into a fresh directory and loads `scene` from it.
fn load_with(files: &[(&str, &str)], scene: &str) -> Result<Scene, SceneError> {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    std::fs::write(dir.path().join("scene.toml"), scene).unwrap();
    let loaded = Scene::load(dir.path().join("scene.toml"));
    drop(dir);
    loaded
}

/// A cube [-2, 2]^3 as an OBJ of n x n quads per face, wound inwards (the normals face the
/// inside): 12 n^2 triangles, through the BVH once there are more than
/// `accel::BRUTE_FORCE_TRIANGLES`.
fn inward_cube_obj(n: usize) -> String {
    let mut obj = String::new();
    let mut count = 0;
    let axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for axis in 0..3 {
        for sign in [1.0, -1.0] {
            // Outward normal n_out, tangents t and b with t x b = n_out.
            let n_out = axes[axis].map(|c| c * sign);
            let t = axes[(axis + 1) % 3].map(|c| c * sign);
            let b = [n_out[1] * t[2] - n_out[2] * t[1], n_out[2] * t[0] - n_out[0] * t[2], n_out[0] * t[1] - n_out[1] * t[0]];
            let point = |i: usize, j: usize| {
                let (u, v) = (-2.0 + 4.0 * i as f64 / n as f64, -2.0 + 4.0 * j as f64 / n as f64);
                std::array::from_fn::<f64, 3, _>(|k| 2.0 * n_out[k] + u * t[k] + v * b[k])
            };
            for i in 0..n {
                for j in 0..n {
                    for p in [point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1)] {
                        obj.push_str(&format!("v {} {} {}\n", p[0], p[1], p[2]));
                    }
                    let q = count + 1;
                    // Counter-clockwise seen from inside: the reverse of (q, q+1, q+2).
                    obj.push_str(&format!("f {} {} {}\nf {} {} {}\n", q, q + 2, q + 1, q, q + 3, q + 2));
                    count += 4;
                }
            }
        }
    }
    obj
}

#[test]
fn a_closed_emitting_box_gives_the_analytic_radiance_for_every_method_and_light_option() {
    let two_sided = scene(&box_scene("[[cubes]]\nmaterial = \"wall\"\ntwo_sided_emission = true\ntransform = { scale = 2 }\n"));
    let one_sided = load_with(&[("box.obj", &inward_cube_obj(1))], &box_scene("[[meshes]]\nfile = \"box.obj\"\nmaterial = \"wall\"\n")).unwrap();
    assert_eq!(one_sided.num_triangles(), 12);
    // 192 triangles (192 lights): through the BVH. `all` would trace 192 shadow rays a vertex.
    let fine = load_with(&[("box.obj", &inward_cube_obj(4))], &box_scene("[[meshes]]\nfile = \"box.obj\"\nmaterial = \"wall\"\n")).unwrap();
    assert!(fine.num_triangles() as u32 > pathlab::accel::BRUTE_FORCE_TRIANGLES);
    use pathlab::method::{LightSelect, TriangleSampling};
    let fine_methods = [
        Preset::Plain.method(),
        Preset::Cosine.method(),
        Preset::Best.method(),
        Method { select: Some(LightSelect::Uniform), triangles: TriangleSampling::SolidAngle, ..Preset::Mis.method() },
        Method { select: Some(LightSelect::Power), ..Preset::Nee.method() },
    ];
    let methods = triangle_light_methods();
    let renders: Vec<(&str, &Scene, Method)> = methods
        .iter()
        .map(|&m| ("two-sided cube", &two_sided, m))
        .chain([Preset::Mis, Preset::Nee, Preset::Best].map(|p| ("one-sided inward OBJ", &one_sided, p.method())))
        .chain(fine_methods.map(|m| ("one-sided inward OBJ of 192 triangles (BVH)", &fine, m)))
        .collect();
    let threshold = z_threshold(0.01, 3 * renders.len());
    let l = expected_radiance();
    let mut report = Vec::new();
    let mut failed = Vec::new();
    for (k, (what, scene, method)) in renders.iter().enumerate() {
        let film = render(scene, *method, 256, 100 + k as u32);
        for c in 0..3 {
            let (mean, err) = image_mean_and_error(&film, c);
            let z = (mean - l) / err.max(1e-12);
            if c == 0 {
                report.push(format!("{what} {}: mean {mean:.5} (expected {l:.5}), z {z:+.2}", method.name()));
            }
            if !(z.abs() <= threshold) {
                failed.push(format!("{what} {} channel {c}: mean {mean}, expected {l}, z = {z:.2}", method.name()));
            }
        }
    }
    println!("{}\n|z| <= {threshold:.2}", report.join("\n"));
    assert!(failed.is_empty(), "{failed:#?}");
}

#[test]
fn a_one_sided_material_scatters_only_on_its_front() {
    // Walls with `two_sided = false`: from inside the outward-facing built-in cube (and inside a
    // sphere) the camera sees their backs, which only emit (two_sided_emission): L = e exactly,
    // every sample, for every method. Wound inwards (the OBJ), the camera sees their fronts and
    // the box gives the analytic L = e (1 - a^d) / (1 - a) (z-tested, alpha = 0.01 over the file's
    // renders and channels). Break: scattering on the back too gives the analytic value from
    // behind (0.47 against 0.25).
    let one_sided = box_scene("").replace("emission = 0.25\n", "emission = 0.25\ntwo_sided = false\n");
    let behind = scene(&format!("{one_sided}[[cubes]]\nmaterial = \"wall\"\ntwo_sided_emission = true\ntransform = {{ scale = 2 }}\n"));
    let sphere = scene(&format!("{one_sided}[[spheres]]\ncenter = [0, 0, 0]\nradius = 3\nmaterial = \"wall\"\n"));
    let front = load_with(&[("box.obj", &inward_cube_obj(1))], &format!("{one_sided}[[meshes]]\nfile = \"box.obj\"\nmaterial = \"wall\"\n")).unwrap();
    assert!(!behind.materials[0].two_sided);
    for (what, s) in [("cube from inside", &behind), ("sphere from inside", &sphere)] {
        for method in [Preset::Plain.method(), Preset::Mis.method(), Preset::Best.method()] {
            let film = render(s, method, 16, 5);
            let worst = film.mean.iter().flatten().fold(0.0f32, |m, &x| m.max((x - EMISSION as f32).abs()));
            assert!(worst < 1e-6, "{what}, {}: the back of a one-sided material scattered (|L - e| up to {worst})", method.name());
        }
    }
    let threshold = z_threshold(0.01, 3 * 3);
    for (k, method) in [Preset::Plain, Preset::Nee, Preset::Best].into_iter().enumerate() {
        let film = render(&front, method.method(), 256, 40 + k as u32);
        for c in 0..3 {
            let (mean, err) = image_mean_and_error(&film, c);
            let z = (mean - expected_radiance()) / err.max(1e-12);
            assert!(z.abs() <= threshold, "front of one-sided walls, {}: mean {mean}, expected {}, z {z:.2}", method.name(), expected_radiance());
        }
    }
}

#[test]
fn one_sided_emitters_are_dark_from_behind() {
    // The built-in cube's faces point outwards: from inside, nothing emits towards the camera,
    // and no light reaches a wall's inner side. The image is black.
    let s = scene(&box_scene("[[cubes]]\nmaterial = \"wall\"\ntransform = { scale = 2 }\n"));
    for method in [Preset::Plain.method(), Preset::Mis.method(), Method { select: Some(pathlab::method::LightSelect::All), ..Preset::Nee.method() }] {
        let film = render(&s, method, 16, 3);
        let max = film.mean.iter().flatten().fold(0.0f32, |m, &x| m.max(x));
        // Not exactly 0: a point on (or, in f32, a hair off) the plane of a light triangle, on
        // the same face or at an edge where faces meet, may see it from in front by rounding
        // (measured: up to 3e-4 of the emission in a pixel, against 1 if the sides were wrong).
        assert!(max < 1e-3 * 0.25, "{}: light from the back of one-sided emitters (max {max})", method.name());
    }
}

#[test]
fn a_traversal_past_the_software_drivers_loop_limit_is_refused_not_averaged() {
    if gpu().info.device_type != wgpu::DeviceType::Cpu {
        return not_run("a_traversal_past_the_software_drivers_loop_limit_is_refused_not_averaged", "needs a CPU (lavapipe) adapter, whose loop limit it tests");
    }
    // 100,000 slivers stacked along the view axis, each just missing it: the camera ray visits
    // every node and tests every triangle, past the 65,535 back-edges llvmpipe allows.
    let mut obj = String::new();
    for k in 0..100_000 {
        let z = -1.0 - k as f64 * 1e-4;
        obj.push_str(&format!("v -1 1.1 {z}\nv 1 1.1 {z}\nv 1 -0.9 {z}\nf -3 -2 -1\n"));
    }
    let text = "[camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, -1]\nup = [0, 1, 0]\nfov_x = 1e-3\n\
                [render]\nwidth = 1\nheight = 1\nmax_depth = 1\nenvironment = 1\n\
                [materials.grey]\ndiffuse = 0.5\n[[meshes]]\nfile = \"slivers.obj\"\nmaterial = \"grey\"\n";
    let s = load_with(&[("slivers.obj", &obj)], text).unwrap();
    let mut r = pathlab::render::Renderer::new(gpu(), pipelines(), &s, Preset::Plain.method(), 0).unwrap();
    r.render(pathlab::render::Budget::Samples(1), &std::sync::atomic::AtomicBool::new(false), |_| {}).unwrap();
    let e = r.readback().expect_err("a cut-short traversal must not be read back as an image");
    assert!(e.to_string().contains("loop limit"), "{e}");
}

/// The first diagnostic of a scene that must be refused.
fn refused(files: &[(&str, &str)], shape: &str) -> pathlab::scene::Diagnostic {
    match load_with(files, &box_scene(shape)) {
        Err(SceneError::Invalid(d)) => d.into_iter().next().unwrap(),
        Err(e) => panic!("not a diagnostic: {e}"),
        Ok(_) => panic!("accepted: {shape}"),
    }
}

#[test]
fn bad_meshes_and_transforms_are_refused_naming_file_line_and_field() {
    let mesh = |file: &str| format!("[[meshes]]\nfile = \"{file}\"\nmaterial = \"wall\"\n");
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    // An index out of range: the OBJ's line.
    let d = refused(&[("m.obj", &format!("{tri}f 1 2 9\n"))], &mesh("m.obj"));
    assert!(d.file.ends_with("m.obj") && d.line == 4 && d.field == "meshes[0].file", "{d}");
    assert!(d.message.contains("refers to no element") && d.message.contains("scene.toml:14"), "{d}");
    // A non-finite vertex.
    let d = refused(&[("m.obj", "v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n")], &mesh("m.obj"));
    assert_eq!(d.line, 2, "{d}");
    // A PLY face out of range.
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
               element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n";
    let d = refused(&[("m.ply", ply)], &mesh("m.ply"));
    assert!(d.line == 13 && d.message.contains("out of range"), "{d}");
    // A missing file, an unknown format.
    let d = refused(&[], &mesh("absent.obj"));
    assert!(d.message.contains("cannot read mesh file"), "{d}");
    let d = refused(&[("m.stl", tri)], &mesh("m.stl"));
    assert!(d.message.contains(".obj, .ply or .serialized"), "{d}");
    // A singular or non-finite transform: the scene's line and the transform's field.
    let d = refused(&[], "[[rectangles]]\nmaterial = \"wall\"\ntransform = { scale = [1, 0, 1] }\n");
    assert!(d.field == "rectangles[0].transform.scale" && d.line == 15 && d.message.contains("singular"), "{d}");
    let d = refused(&[], "[[cubes]]\nmaterial = \"wall\"\ntransform = { matrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]] }\n");
    assert!(d.field == "cubes[0].transform.matrix" && d.message.contains("affine"), "{d}");
    let d = refused(&[], "[[cubes]]\nmaterial = \"wall\"\ntransform = { rotate = { axis = [0, 0, 0], angle = 10 } }\n");
    assert!(d.field == "cubes[0].transform.rotate", "{d}");
    // An emissive mesh of zero total area (every triangle degenerate).
    let d = refused(&[("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")], &mesh("flat.obj"));
    assert!(d.field == "meshes[0].material" && d.message.contains("total area is zero"), "{d}");
}

#[test]
fn degenerate_triangles_are_dropped_with_one_warning_that_counts_them() {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 2 4 1\nf 3 3 3\n";
    let s = load_with(&[("m.obj", obj)], &box_scene("[[meshes]]\nfile = \"m.obj\"\nmaterial = \"wall\"\n")).unwrap();
    assert_eq!(s.num_triangles(), 1);
    let warnings: Vec<_> = s.warnings.iter().filter(|w| w.message.contains("zero area")).collect();
    assert_eq!(warnings.len(), 1, "{:?}", s.warnings);
    assert!(warnings[0].message.starts_with("3 of 4 triangles"), "{}", warnings[0]);
}

/// Split renders of a mesh scene merge to the single run, with the light options recorded in
/// each part: parts of different light selections are refused.
#[test]
fn cornell_box_shards_merge_to_the_single_run_and_light_options_must_agree() {
    use std::process::Command;
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/cornell_box.toml");
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_pathlab")).args(args).output().unwrap();
        (out.status.success(), String::from_utf8_lossy(&out.stderr).into_owned())
    };
    let p = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let common = ["--width", "16", "--height", "16", "--method", "mis", "--light-select", "uniform", "--triangle-sampling", "solid-angle", "--quiet"];
    let (ok, e) = run(&[&["render", scene, "--spp", "24", "-o", &p("single.exr")][..], &common].concat());
    assert!(ok, "{e}");
    for (range, name) in [("0..10", "a.exr"), ("10..24", "b.exr")] {
        let (ok, e) = run(&[&["render", scene, "--samples", range, "-o", &p(name)][..], &common].concat());
        assert!(ok, "{e}");
    }
    let (ok, e) = run(&["merge", &p("a.exr"), &p("b.exr"), "-o", &p("merged.exr")]);
    assert!(ok, "{e}");
    let (single, _) = pathlab::output::read_exr(std::path::Path::new(&p("single.exr"))).unwrap();
    let (merged, _) = pathlab::output::read_exr(std::path::Path::new(&p("merged.exr"))).unwrap();
    assert_eq!(merged.spp, 24);
    let worst = single.mean.iter().flatten().zip(merged.mean.iter().flatten()).map(|(a, b)| ((a - b).abs() / a.abs().max(1e-3)) as f64).fold(0.0, f64::max);
    assert!(worst <= 2e-6, "merged differs from the single run by {worst:e}");
    // A part of another light selection does not belong to this render.
    let other: Vec<&str> = common.iter().map(|&a| if a == "uniform" { "power" } else { a }).collect();
    let (ok, e) = run(&[&["render", scene, "--samples", "10..24", "-o", &p("c.exr")][..], &other].concat());
    assert!(ok, "{e}");
    let (ok, e) = run(&["merge", &p("a.exr"), &p("c.exr"), "-o", &p("bad.exr")]);
    assert!(!ok && e.contains("light_select"), "{e}");
}

/// The two tunings of the kernel render the same images (`gpu::AdapterTuning`): a CPU
/// adapter's (small scenes triangle by triangle, the stackless traversal, plain edge
/// functions, spheres, planes and quadrics read from registers, each light of next event
/// estimation at a constant index) and a GPU's (every scene through the BVH, with a stack,
/// ordered edge functions, the shapes read from their uniform buffers, the lights in a loop),
/// both run here, bit for bit. The study scene (4 spheres, 2 planes), Veach's scene (3
/// spherical lights) and the quadrics fixture (disks and cylinders, lights among them) hold the
/// registers' copies to the uniform buffers, and the unrolled visits of their lights to the
/// loop (`mis` and `best` visit every light there). The Cornell box (36
/// triangles) and Veach's scene (52) are the only CI coverage of small scenes through the BVH
/// and of the traversal with a stack in a render; the lamps (404 triangles) hold the stackless
/// traversal to it. Both ways find the nearest triangle with the same watertight test (the
/// small scenes' on their shared vertices, the same operations) and the traversals visit the
/// nodes in the same order; only a tie at one distance could resolve to another triangle, and
/// the Cornell box's ties (a quad's diagonal) lie between coplanar triangles of one material
/// and one light.
#[test]
fn the_cpu_and_gpu_tunings_render_the_same_images() {
    use pathlab::gpu::{AdapterTuning, PathTracerPipelines};
    use pathlab::render::Renderer;
    let gpu_tuning = AdapterTuning::for_device(wgpu::DeviceType::DiscreteGpu);
    let mut cpu_tuning = AdapterTuning::for_device(wgpu::DeviceType::Cpu);
    assert!(gpu_tuning.brute_force_limit == 0 && !gpu_tuning.stackless_traversal && gpu_tuning.ordered_edges && !gpu_tuning.scene_in_registers && !gpu_tuning.lights_unrolled);
    assert!(cpu_tuning.stackless_traversal && !cpu_tuning.ordered_edges && cpu_tuning.scene_in_registers && cpu_tuning.lights_unrolled);
    // Where the adapter fuses multiply-adds (a GPU), the CPU tuning's plain edge functions let
    // rays through shared edges (what ORDERED_EDGES is for): there both tunings run with the
    // edge functions this adapter needs, so that what differs is the traversal alone (the small
    // scenes' triangle-by-triangle tests, the stackless traversal).
    if gpu().info.device_type != wgpu::DeviceType::Cpu {
        cpu_tuning.ordered_edges = true;
    }
    let tuned = [gpu_tuning, cpu_tuning].map(|t| PathTracerPipelines::with_tuning(&gpu().device, t));
    for file in ["assets/scenes/cornell_box.toml", "assets/scenes/veach_mis.xml", "assets/scenes/lamps.xml", "assets/scenes/study.toml", "tests/fixtures/quadrics/quadrics.xml"] {
        let mut scene = Scene::load(format!("{}/{file}", env!("CARGO_MANIFEST_DIR"))).unwrap();
        (scene.render.width, scene.render.height) = (24, 24);
        for preset in [Preset::Mis, Preset::Best] {
            let [a, b] = [&tuned[0], &tuned[1]].map(|p| finish(Renderer::new(gpu(), p, &scene, preset.method(), 5).expect("renderer"), 16).film);
            assert!(a.mean.iter().flatten().any(|&x| x > 0.0));
            let differing = bits(&a).iter().zip(bits(&b).iter()).filter(|(x, y)| x != y).count();
            assert!(differing == 0, "{file} {}: the GPU's tuning renders another image than the CPU's ({differing} of {} values differ)", preset.name(), bits(&a).len());
        }
    }
    let triangles = |file: &str| Scene::load(format!("{}/assets/scenes/{file}", env!("CARGO_MANIFEST_DIR"))).unwrap().num_triangles() as u32;
    assert!(triangles("veach_mis.xml") <= pathlab::accel::BRUTE_FORCE_TRIANGLES && triangles("lamps.xml") > pathlab::accel::BRUTE_FORCE_TRIANGLES);
}

/// A floor 2000 units wide lights as one 20 wide. Its triangles' vertices are 1000 from the
/// origin, so the hit's t (from the sheared test, which errs by the vertices' magnitude times
/// f32 precision, ~1e-4) and the shadow ray's test against the floor erred by more than the
/// 2e-5 ray offset, and shadow rays found the floor again: before Hit.p_error (an error bound
/// from the vertices, which the offset respects), this tilted floor under a point light
/// rendered 16% too dark (mean 0.1021 against 0.1220; Mitsuba 3.9.1: 0.1220). Both floors, same samples: the
/// images must agree to rounding (not a statistical test: the same seed places the same
/// samples on both, and no sample may be lost).
#[test]
fn a_floor_a_thousand_times_larger_than_the_view_loses_no_light() {
    let scene = |scale: u32| {
        format!(
            r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="2"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="120"/>
        <transform name="to_world"><lookat origin="0, 0, 1" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="48"/><integer name="height" value="48"/><rfilter type="box"/></film>
    </sensor>
    <emitter type="point"><point name="position" value="0, 0, 1"/><rgb name="intensity" value="1"/></emitter>
    <shape type="rectangle">
        <transform name="to_world"><scale value="{scale}"/><rotate x="1" angle="25"/><rotate y="1" angle="15"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf>
    </shape>
</scene>"#
        )
    };
    let render_mean = |scale: u32| {
        let s = load_xml(&scene(scale), "floor.xml").unwrap();
        let film = render(&s, Preset::Mis.method(), 64, 4400);
        (film.mean.iter().map(|p| p[0] as f64).sum::<f64>() / film.mean.len() as f64, film)
    };
    let (large, large_film) = render_mean(1000);
    let (small, small_film) = render_mean(10);
    println!("image mean: floor 2000 wide {large:.5}, 20 wide {small:.5}");
    assert!((large / small - 1.0).abs() < 1e-4, "the large floor's image mean {large} against the small one's {small}");
    let worst = large_film.mean.iter().zip(&small_film.mean).map(|(a, b)| (a[0] - b[0]).abs() as f64).fold(0.0, f64::max);
    assert!(worst < 1e-2 * small, "a pixel differs by {worst} (the image mean is {small})");
}
