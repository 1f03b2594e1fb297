//! Shared helpers of the integration tests: two GPU devices, each with its pipeline cache, a
//! test on the one fewer running tests use (`slot`).
#![allow(dead_code)]

use std::sync::atomic::AtomicBool;
use std::sync::OnceLock;

use pathlab::gpu::{Gpu, PathTracerPipelines};
use pathlab::method::Method;
use pathlab::render::{Budget, Readback, Renderer};
use pathlab::film::Film;
use pathlab::scene::Scene;

/// Devices the tests share. libtest runs each test on a thread of its own, two at once on this
/// 2-core machine; a device has one queue, which runs its dispatches one after another, so two
/// tests on one device wait for each other's, and as a dispatch ends, the few workgroups left
/// keep one core busy and the other idle (the suite ran 14% idle with one device, README
/// "Tests"). On two devices lavapipe's compute threads, one pool for all of its devices, take
/// the dispatches of both queues at once.
const DEVICES: usize = 2;

static GPUS: [OnceLock<Gpu>; DEVICES] = [const { OnceLock::new() }; DEVICES];
static PIPELINES: [OnceLock<PathTracerPipelines>; DEVICES] = [const { OnceLock::new() }; DEVICES];

/// Pipelines a device's cache keeps once no running test uses it, for the tests after it (the
/// study scene's presets), without holding every test's: lavapipe keeps each pipeline's code,
/// and a test of one heterogeneous medium peaked at 1.24 GB with its two, the Cornell box's
/// test at 462 MB with its 22; the 48 of `CACHED_PIPELINES` on each device held the suite at
/// 10.6 GB (2026-12-07).
const KEPT_BETWEEN_TESTS: usize = 4;

/// The device of this test (its thread): the one fewest running tests use, taken at the test's
/// first call and given back when its thread ends.
fn slot() -> usize {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static USERS: [AtomicUsize; DEVICES] = [const { AtomicUsize::new(0) }; DEVICES];
    struct Taken(usize);
    impl Drop for Taken {
        fn drop(&mut self) {
            if USERS[self.0].fetch_sub(1, Ordering::Relaxed) == 1 {
                if let Some(pipelines) = PIPELINES[self.0].get() {
                    pipelines.retain_recent(KEPT_BETWEEN_TESTS);
                }
            }
        }
    }
    thread_local! {
        static SLOT: Taken = {
            let k = (0..DEVICES).min_by_key(|&k| USERS[k].load(Ordering::Relaxed)).unwrap();
            USERS[k].fetch_add(1, Ordering::Relaxed);
            Taken(k)
        };
    }
    SLOT.with(|s| s.0)
}

pub fn gpu() -> &'static Gpu {
    GPUS[slot()].get_or_init(|| Gpu::new(None).expect("a Vulkan adapter (lavapipe in CI)"))
}

/// How much more work a test that must be interrupted mid-way gives a GPU than lavapipe: its
/// sample counts are sized for lavapipe, where they take seconds; an NVIDIA H200 finished them
/// before the kill (2026-12-04), and at 2000 times the work it took over a minute on these
/// tiny images (a factor chosen between the two, not yet run there).
pub fn work_scale() -> u64 {
    if gpu().info.device_type == wgpu::DeviceType::Cpu { 1 } else { 200 }
}

/// The pipeline cache of this test's device.
pub fn pipelines() -> &'static PathTracerPipelines {
    PIPELINES[slot()].get_or_init(|| PathTracerPipelines::new(&gpu()))
}

pub fn scene(text: &str) -> Scene {
    Scene::parse(text, "test.toml").unwrap_or_else(|e| panic!("test scene is invalid:\n{e}"))
}

/// Three numbers of a JSON fixture.
#[allow(dead_code)]
pub fn json_v3(v: &serde_json::Value) -> [f64; 3] {
    let a = v.as_array().unwrap();
    [a[0].as_f64().unwrap(), a[1].as_f64().unwrap(), a[2].as_f64().unwrap()]
}

/// The kernel's f and pdf of `bsdf` (`eval_bsdf_pairs`) against Mitsuba's own at each pair of a
/// fixture made by `scripts/*_evals.py` (`wo`, `wi`, `f`, `pdf`), and reciprocity: f within
/// `f_tol` (relative, absolute) of Mitsuba's, the pdf within `pdf_tol`, f(wi, wo) = f(wo, wi) to
/// 1e-4 (relative, or 1e-6). `what` names the material in messages. Returns the largest
/// differences relative to the value plus 1e-2 (f, pdf).
#[allow(dead_code)]
pub fn agrees_with_mitsuba_evals(bsdf: &pathlab::scene::Bsdf, pairs_json: &[serde_json::Value], what: &str, f_tol: (f64, f64), pdf_tol: (f64, f64)) -> (f64, f64) {
    let pairs: Vec<[f32; 4]> = pairs_json
        .iter()
        .flat_map(|pair| [json_v3(&pair["wo"]), json_v3(&pair["wi"])])
        .map(|d| [d[0] as f32, d[1] as f32, d[2] as f32, 0.0])
        .collect();
    let out = eval_bsdf_pairs(bsdf, &pairs);
    let (mut worst_f, mut worst_pdf) = (0.0f64, 0.0f64);
    for (i, pair) in pairs_json.iter().enumerate() {
        let (f, pdf) = (json_v3(&pair["f"]), pair["pdf"].as_f64().unwrap());
        let (fwd, bwd) = (out[2 * i], out[2 * i + 1]);
        let at = format!("{what} wo {} wi {}", pair["wo"], pair["wi"]);
        for ch in 0..3 {
            let (got, back) = (fwd[ch] as f64, bwd[ch] as f64);
            worst_f = worst_f.max((got - f[ch]).abs() / (f[ch] + 1e-2));
            assert!((got - f[ch]).abs() <= f_tol.0 * f[ch] + f_tol.1, "{at}: f channel {ch} is {got}, Mitsuba's {}", f[ch]);
            // Reciprocity where both directions are on one side: a transmission's f is not
            // symmetric in Mitsuba's definitions (radiance's 1 / eta^2; the thin principled
            // BSDF's masks look at the viewer's side).
            let reflection = json_v3(&pair["wo"])[2] * json_v3(&pair["wi"])[2] > 0.0;
            assert!(!reflection || (got - back).abs() <= 1e-4 * got + 1e-6, "{at}: f(wi, wo) = {got} but f(wo, wi) = {back}");
        }
        let got = fwd[3] as f64;
        worst_pdf = worst_pdf.max((got - pdf).abs() / (pdf + 1e-2));
        assert!((got - pdf).abs() <= pdf_tol.0 * pdf + pdf_tol.1, "{at}: pdf {got}, Mitsuba's {pdf}");
    }
    (worst_f, worst_pdf)
}

/// A 4x4 TOML scene of one sphere of material `m` under a white environment, `material` the
/// lines of its `[materials.m]` table: for tests of a BSDF's fields.
#[allow(dead_code)]
pub fn toml_with_material(material: &str) -> String {
    format!(
        "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 60\n\
         [render]\nwidth = 4\nheight = 4\nmax_depth = 2\nenvironment = 1\n\
         [materials.m]\n{material}\n[[spheres]]\ncenter = [0, 0, -3]\nradius = 1\nmaterial = \"m\"\n"
    )
}

/// A 4x4 Mitsuba XML scene of one sphere whose BSDF is `bsdf`, given on line 3 with id `id`: for
/// tests of a plugin's properties.
#[allow(dead_code)]
pub fn xml_with_bsdf(bsdf: &str, id: &str) -> String {
    format!(
        "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"45\"/>\
         <film type=\"hdrfilm\"><integer name=\"width\" value=\"4\"/><integer name=\"height\" value=\"4\"/></film></sensor>\n\
         {bsdf}\n<shape type=\"sphere\"><ref id=\"{id}\"/></shape>\n</scene>\n"
    )
}

/// A Mitsuba XML scene from its text, written as file `name` in a folder of its own (diagnostics
/// name it).
#[allow(dead_code)]
pub fn load_xml(text: &str, name: &str) -> Result<Scene, pathlab::scene::SceneError> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    Scene::load(&path)
}

/// f(wi, wo) with the pdf of the own strategy, and f(wo, wi), of `bsdf` (shading normal +z; a
/// viewer's direction below the surface sees it from inside: `Bsdf.inside`, the normal turned
/// towards it, as the integrator does) at each pair (wo, wi) of `pairs` (even entries wo, odd wi), computed by
/// the kernel's `eval_pdf_bsdf` with the BSDF's data bound: per pair, `[f, pdf]` then `[f
/// reversed, 0]`.
#[allow(dead_code)]
pub fn eval_bsdf_pairs(bsdf: &pathlab::scene::Bsdf, pairs: &[[f32; 4]]) -> Vec<[f32; 4]> {
    let kind = bsdf.kind().stem().to_uppercase();
    let kernel = format!(
        "struct TestParams {{ p0: vec4f, p1: vec4f, p2: vec4f, p3: vec4f, count: u32, _a: u32, _b: u32, _c: u32 }}\n\
         @group(0) @binding(0) var<storage, read> test_params: TestParams;\n\
         @group(0) @binding(1) var<storage, read_write> test_out: array<vec4f>;\n\
         @group(0) @binding(2) var<storage, read> test_dirs: array<vec4f>;\n\
         @compute @workgroup_size(64)\n\
         fn eval_main(@builtin(global_invocation_id) gid: vec3u) {{\n\
             let i = gid.x;\n\
             if (i >= test_params.count) {{ return; }}\n\
             var b = Bsdf(BSDF_KIND_{kind}, test_params.p0, test_params.p1, test_params.p2, test_params.p3, false, 1.0, vec3f(1.0, 0.0, 0.0), vec3f(0.0));\n\
             let wo = test_dirs[2u * i].xyz;\n\
             let wi = test_dirs[2u * i + 1u].xyz;\n\
             b.inside = wo.z < 0.0;\n\
             let forward = eval_pdf_bsdf(b, select(vec3f(0.0, 0.0, 1.0), vec3f(0.0, 0.0, -1.0), b.inside), wo, wi);\n\
             b.inside = wi.z < 0.0;\n\
             let backward = eval_pdf_bsdf(b, select(vec3f(0.0, 0.0, 1.0), vec3f(0.0, 0.0, -1.0), b.inside), wi, wo);\n\
             test_out[2u * i] = vec4f(forward.f, forward.pdf);\n\
             test_out[2u * i + 1u] = vec4f(backward.f, 0.0);\n\
         }}\n"
    );
    let mut data = pathlab::scene::BsdfData::default();
    let packed = bsdf.pack(&mut data);
    let count = pairs.len() / 2;
    let mut params: Vec<f32> = packed.iter().flatten().copied().collect();
    params.extend([f32::from_bits(count as u32), 0.0, 0.0, 0.0]);
    let mut inputs = vec![(0, bytemuck::cast_slice(&params).to_vec()), (2, bytemuck::cast_slice(pairs).to_vec())];
    if !data.0.is_empty() {
        inputs.push((pathlab::shaders::bindings::BSDF_DATA.number, bytemuck::cast_slice(&data.0).to_vec()));
    }
    let source = pathlab::shaders::assemble(&pathlab::shaders::LIBRARY, &kernel);
    let run = pathlab::gpu::KernelRun {
        source: &source,
        entry: "eval_main",
        constants: &[],
        inputs,
        uniforms: vec![],
        texel_tables: vec![],
        output: (1, (pairs.len() * 16) as u64),
        workgroups: (count as u32).div_ceil(64),
    };
    bytemuck::pod_collect_to_vec(&run.run(gpu()).unwrap_or_else(|e| panic!("{} eval kernel: {e}", bsdf.kind().name())))
}

/// Runs a test kernel's `entry` (one invocation per item of the storage input at binding 0,
/// `items` of them, 64 per workgroup) assembled after `parts`, with the storage `inputs` and
/// `out_per_item` vec4s out per item at binding 1; returns them.
#[allow(dead_code)]
pub fn run_test_kernel(parts: &[(&str, &str)], kernel: &str, entry: &str, inputs: Vec<(u32, Vec<u8>)>, items: usize, out_per_item: usize) -> Vec<[f32; 4]> {
    let source = pathlab::shaders::assemble(parts, kernel);
    let run = pathlab::gpu::KernelRun {
        source: &source,
        entry,
        constants: &[],
        inputs,
        uniforms: vec![],
        texel_tables: vec![],
        output: (1, (items * out_per_item * 16) as u64),
        workgroups: (items as u32).div_ceil(64),
    };
    bytemuck::pod_collect_to_vec(&run.run(gpu()).unwrap_or_else(|e| panic!("{entry}: {e}")))
}

pub fn study_scene() -> Scene {
    Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/study.toml")).expect("study scene")
}

/// Renders `spp` samples per pixel in one call.
pub fn render(scene: &Scene, method: Method, spp: u64, seed: u32) -> Film {
    let r = Renderer::new(gpu(), pipelines(), scene, method, seed).expect("renderer");
    finish(r, spp).film
}

/// Renders `spp` samples per pixel with `renderer` and reads back film and ray count.
pub fn finish(mut renderer: Renderer, spp: u64) -> Readback {
    renderer.render(Budget::Samples(spp), &AtomicBool::new(false), |_| {}).expect("render");
    renderer.readback().expect("readback")
}

/// Bit patterns of every mean and variance value, for exact comparisons.
pub fn bits(film: &Film) -> Vec<u32> {
    film.mean.iter().chain(&film.variance).flatten().map(|x| x.to_bits()).collect()
}

use pathlab::method::{Preset, Sampler};

/// Every unbiased method the suite holds to the contract: the presets, `mis` with the balance
/// heuristic, and `mis` with each sampler.
pub fn unbiased_methods() -> Vec<(String, Method)> {
    let mut methods: Vec<(String, Method)> = Preset::ALL.iter().map(|p| (p.name().to_string(), p.method())).collect();
    let balance = Method { lights: pathlab::method::LightSampling::MisBalance, ..Preset::Mis.method() };
    methods.push((balance.name(), balance));
    for sampler in Sampler::ALL {
        let m = Method { sampler, ..Preset::Mis.method() };
        if !methods.iter().any(|(_, x)| *x == m) {
            methods.push((format!("mis+{}", sampler.name()), m));
        }
    }
    methods
}

/// The two deliberately biased demonstration methods.
pub fn biased_methods() -> Vec<(String, Method)> {
    pathlab::method::biased_demonstrations().into_iter().map(|(n, m)| (n.to_string(), m)).collect()
}

/// A film of the constant `value` with zero variance, as a reference for z-tests.
pub fn constant_film(width: u32, height: u32, value: f32) -> Film {
    let n = (width * height) as usize;
    Film { width, height, spp: u64::MAX, mean: vec![[value; 3]; n], variance: vec![[0.0; 3]; n] }
}

/// Says that a test did not run, and why, where `cargo test` shows it to the user: straight to
/// the process's stderr, past the test harness's output capture (which would hide it, and show
/// the test as passed). The test itself then passes having run nothing, so CI refuses to skip
/// (the callers assert `CI` is unset).
pub fn not_run(test: &str, why: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "\n    NOT RUN: {test}: {why}\n");
}

/// Every unbiased preset, and each preset that samples lights with every light selection and
/// triangle sampling, and `mis` with the balance heuristic: the methods a scene with triangle
/// lights is held to.
pub fn triangle_light_methods() -> Vec<Method> {
    let mut methods = triangle_light_methods_of(&Preset::ALL);
    methods.push(Method { lights: pathlab::method::LightSampling::MisBalance, ..Preset::Mis.method() });
    methods
}

/// `presets`, and each of them that samples lights with every light selection and triangle
/// sampling.
pub fn triangle_light_methods_of(presets: &[Preset]) -> Vec<Method> {
    use pathlab::method::{LightSampling, LightSelect, TriangleSampling};
    let mut methods = Vec::new();
    for &preset in presets {
        let base = preset.method();
        if base.lights == LightSampling::None {
            methods.push(base);
            continue;
        }
        for select in LightSelect::ALL {
            for triangles in TriangleSampling::ALL {
                methods.push(Method { select: Some(select), triangles, ..base });
            }
        }
    }
    methods
}

/// A Mitsuba reference fixture (`tests/fixtures/NAME/`: reference.exr, reference_var.exr with
/// the variance of its mean, reference.json): mean and variance as one film.
#[allow(dead_code)]
pub fn mitsuba_fixture(name: &str) -> Film {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(name);
    let read = |f: &str| pathlab::output::read_exr_image(&dir.join(f)).unwrap_or_else(|e| panic!("tests/fixtures/{name}/{f}: {e}")).film;
    let (mean, var) = (read("reference.exr"), read("reference_var.exr"));
    let record: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("reference.json")).unwrap()).unwrap();
    assert_eq!(record["mitsuba_version"], "3.9.1");
    Film { spp: record["spp"].as_u64().unwrap(), variance: var.mean, ..mean }
}

/// Renders `scene` with every method (sample count and block size from `plan`, seeds from
/// `first_seed`) and z-tests each against `reference` on blocks, Šidák-corrected over the
/// channels and over the renders plus one (the power check): at least 99.75% of a render's
/// channels must pass. Then the render of `scaled` (its image times 1.05) must be rejected on
/// its blocks. Panics with the report on any failure; returns the renders, in `methods`' order.
#[allow(dead_code)]
pub fn agrees_with_reference(reference: &Film, scene: &Scene, methods: &[Method], plan: impl Fn(&Method) -> (u64, u32), first_seed: u32, scaled: Method) -> Vec<Film> {
    use pathlab::stats::{sidak, z_test};
    const MIN_PASS: f64 = 0.9975;
    let alpha = sidak(0.01, methods.len() + 1);
    let mut report = Vec::new();
    let mut failed = Vec::new();
    let mut power = None;
    let mut films = Vec::new();
    for (k, method) in methods.iter().enumerate() {
        let (spp, block) = plan(method);
        let film = render(scene, *method, spp, first_seed + k as u32);
        films.push(film.clone());
        let z = z_test(&reference.downsample(block), &film.downsample(block), alpha);
        report.push(format!(
            "{} ({spp} spp, {block}x{block} blocks): {:.4} of {} channels pass |z| <= {:.2}; max |z| {:.2}, mean z {:+.3}",
            method.name(),
            z.pass_fraction,
            z.channels,
            z.threshold,
            z.max_abs_z,
            z.mean_z
        ));
        if z.pass_fraction < MIN_PASS {
            failed.push(method.name());
        }
        if *method == scaled && power.is_none() {
            power = Some((film, block));
        }
    }
    println!("{}", report.join("\n"));
    assert!(failed.is_empty(), "disagree with the reference: {failed:?}\n{}", report.join("\n"));
    let (mut biased, block) = power.expect("the scaled method is one of the methods");
    biased.mean.iter_mut().flatten().for_each(|c| *c *= 1.05);
    let z = z_test(&reference.downsample(block), &biased.downsample(block), alpha);
    assert!(z.pass_fraction < MIN_PASS, "a 5% bias passes: {:.4}", z.pass_fraction);
    films
}

/// The error of loading `dir/bad.xml`, a Mitsuba scene of a camera and a rectangle light on
/// its first two lines and `shape` on its third.
pub fn xml_shape_error(dir: &std::path::Path, shape: &str) -> String {
    let xml = format!("<scene version=\"3.0.0\"><sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>\n<shape type=\"rectangle\"><emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter></shape>\n{shape}\n</scene>");
    std::fs::write(dir.join("bad.xml"), xml).unwrap();
    Scene::load(dir.join("bad.xml")).unwrap_err().to_string()
}

/// The host's nearest hit of the ray o + t d (t > 0) over the scene's quadrics (disks,
/// cylinders, curve segments, SDF grids), each by its f64 definition: (t, quadric index).
pub fn nearest_quadric_hit(scene: &Scene, o: glam::DVec3, d: glam::DVec3) -> Option<(f64, usize)> {
    scene.quadrics.iter().enumerate().filter_map(|(i, q)| q.intersect(o, d, 0.0, f64::INFINITY).map(|t| (t, i))).min_by(|a, b| a.0.total_cmp(&b.0))
}

/// What `intersect_scene` returns for one ray (`Hit`, intersect.wgsl).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TracedHit {
    pub t: f32,
    pub normal: [f32; 3],
    /// The kernel's object index (`u32::MAX`: a miss).
    pub object: u32,
    pub uv: [f32; 2],
    /// The shading normal (a mesh's interpolated vertex normal, an SDF grid's smooth normal;
    /// else the geometric normal).
    pub shading_normal: [f32; 3],
}

const TRACE_KERNEL: &str = r#"
struct ProbeRay { o: vec4f, d: vec4f }
@group(0) @binding(30) var<storage, read> probe_rays: array<ProbeRay>;
@group(0) @binding(31) var<storage, read_write> probe_out: array<vec4f>;

@compute @workgroup_size(64)
fn trace_probe(@builtin(global_invocation_id) gid: vec3u) {
    load_scene_registers();
    let i = gid.x;
    if (i >= arrayLength(&probe_rays)) {
        return;
    }
    let hit = intersect_scene(probe_rays[i].o.xyz, probe_rays[i].d.xyz);
    probe_out[3u * i] = vec4f(hit.uv, bitcast<f32>(hit.object), hit.t);
    probe_out[3u * i + 1u] = vec4f(hit.normal, 0.0);
    probe_out[3u * i + 2u] = vec4f(hit.shading_normal, 0.0);
}
"#;

/// Traces `rays` (origin, unit direction) through `scene` in a kernel built from the path
/// tracer's own WGSL with the scene's own buffers (`SceneBuffers::contents`) and the pipeline
/// constants of `features`: the kernel's `intersect_scene`, each ray's hit.
pub fn trace_hits(scene: &Scene, features: pathlab::gpu::SceneFeatures, rays: &[(glam::DVec3, glam::DVec3)]) -> Vec<TracedHit> {
    trace_hits_keyed(scene, pathlab::gpu::PipelineKey::new(Preset::Mis.method(), features, scene.default_light_select()), rays)
}

/// `trace_hits` with the kernel specialised to `key`.
pub fn trace_hits_keyed(scene: &Scene, key: pathlab::gpu::PipelineKey, rays: &[(glam::DVec3, glam::DVec3)]) -> Vec<TracedHit> {
    use pathlab::gpu::{pipeline_constants, KernelRun, PackedTriangles, SceneBuffers};
    use pathlab::shaders::{self, bindings};
    let packed = PackedTriangles::new(scene, false);
    let constants = pipeline_constants(&key);
    let source = shaders::assemble(&shaders::PATH_TRACER, TRACE_KERNEL);
    let (mut inputs, mut uniforms, mut texel_tables) = (vec![], vec![], vec![]);
    for c in SceneBuffers::contents(scene, &packed) {
        match c.binding.kind {
            bindings::Kind::Uniform => uniforms.push((c.binding.number, c.bytes)),
            bindings::Kind::Storage { .. } => inputs.push((c.binding.number, c.bytes)),
            bindings::Kind::TexelTable => texel_tables.push((c.binding.number, c.bytes)),
        }
    }
    let rays: Vec<[f32; 8]> = rays
        .iter()
        .map(|(o, d)| {
            let (o, d) = (o.as_vec3(), d.as_vec3());
            [o.x, o.y, o.z, 0.0, d.x, d.y, d.z, 0.0]
        })
        .collect();
    inputs.push((30, bytemuck::cast_slice(&rays).to_vec()));
    let run = KernelRun {
        source: &source,
        entry: "trace_probe",
        constants: &constants,
        inputs,
        uniforms,
        texel_tables,
        output: (31, rays.len() as u64 * 48),
        workgroups: (rays.len() as u32).div_ceil(64),
    };
    let out: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&run.run(gpu()).expect("trace kernel"));
    out.chunks(3)
        .map(|h| TracedHit { t: h[0][3], normal: [h[1][0], h[1][1], h[1][2]], object: h[0][2].to_bits(), uv: [h[0][0], h[0][1]], shading_normal: [h[2][0], h[2][1], h[2][2]] })
        .collect()
}

/// A scratch folder for one test's files (`pathlab-<name>-XXXXXX` in the system's temporary
/// folder), removed when it is dropped; it derefs to its path.
#[allow(dead_code)]
pub struct ScratchDir(tempfile::TempDir);

#[allow(dead_code)]
pub fn scratch_dir(name: &str) -> ScratchDir {
    ScratchDir(tempfile::Builder::new().prefix(&format!("pathlab-{name}-")).tempdir().unwrap())
}

impl std::ops::Deref for ScratchDir {
    type Target = std::path::Path;
    fn deref(&self) -> &std::path::Path {
        self.0.path()
    }
}

impl AsRef<std::path::Path> for ScratchDir {
    fn as_ref(&self) -> &std::path::Path {
        self.0.path()
    }
}
