//! Path-tracing pipelines, specialised through WGSL `override` constants to a method and to the
//! features of a scene, created once per (method, features) and cached.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use wgpu::util::DeviceExt;

use crate::method::{LightSampling, LightSelect, Method};
use super::features::SceneFeatures;
use super::recent::Recent;
use crate::scene::{BsdfKind, EmitterKind};
use crate::shaders::specialise::{self, ParsedModule};
use crate::shaders::{self, bindings};

/// `TRAVERSAL_BUDGET` of a pipeline whose traversal is bounded by the host: no guard.
pub const NO_TRAVERSAL_GUARD: u32 = u32::MAX;

/// What a pipeline is specialised to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PipelineKey {
    /// The method, its light selection resolved (`Some`).
    pub method: Method,
    pub features: SceneFeatures,
    /// Traversal steps an invocation may take before the kernel's guard drops its sample
    /// (`NO_TRAVERSAL_GUARD`: none).
    pub traversal_budget: u32,
    /// B-spline segments are searched by unrolled code (`BSPLINE_UNROLLED`,
    /// quadrics/bspline_curve.wgsl): no loop back-edges, for scenes whose looped searches
    /// would pass llvmpipe's loop budget; half the speed on lavapipe.
    pub bspline_unrolled: bool,
    /// The BVH has a leaf deeper than 32 levels (`Bvh::depth`): the stackless traversal keeps
    /// its trail of bits in two words (`BVH_DEEP`, bvh.wgsl), else in one. True where the BVH is
    /// not known, which is correct for any depth.
    pub deep_bvh: bool,
}

/// The deepest BVH whose stackless traversal keeps its trail of bits in one word.
pub const ONE_WORD_TRAIL_DEPTH: usize = 32;

impl PipelineKey {
    /// The key of `method` on a scene with `features`: `default_select` (the scene's,
    /// `Scene::default_light_select`) where the method leaves the selection open, no traversal
    /// guard. The environment is a light of the table only where the method samples it
    /// (`Method::environment`, with light sampling on); every plane and every triangle can then
    /// block a shadow ray, which runs to infinity.
    pub fn new(method: Method, mut features: SceneFeatures, default_select: LightSelect) -> PipelineKey {
        let select = Some(method.select.unwrap_or(default_select));
        if !(method.environment && method.lights != LightSampling::None) {
            features.num_environment_lights = 0;
        }
        if features.num_environment_lights > 0 {
            features.num_occluding_planes = features.num_planes;
            features.small_vertices = features.small_vertices.with_shadow_tests(u64::MAX);
        }
        PipelineKey { method: Method { select, ..method }, features, traversal_budget: NO_TRAVERSAL_GUARD, bspline_unrolled: false, deep_bvh: true }
    }

    /// Whether the light table holds the environment (`Scene::sampled_lights`).
    pub fn samples_environment(&self) -> bool {
        self.features.num_environment_lights > 0
    }
}

/// The `override` constants of the path tracer for a method and scene features.
pub fn pipeline_constants(key: &PipelineKey) -> Vec<(&'static str, f64)> {
    let f = &key.features;
    // Power selection over lights of equal power is uniform selection, exactly: the kernel then
    // reads no table (storage reads at a per-lane index, slow on lavapipe; the Cornell box's two
    // light triangles: `mis` +5% M samples/s, median of 3), and draws the same lights.
    let select = match key.method.select.unwrap_or(LightSelect::All) {
        LightSelect::Power if f.uniform_light_powers && f.num_environment_lights == 0 => LightSelect::Uniform,
        select => select,
    };
    // One HAS_<KIND> per BSDF kind of the registry.
    let kinds = BsdfKind::ALL.map(|k| (k.has_override(), (f.bsdf_kinds & k.bit() != 0) as u32 as f64));
    // One <STEM>_TRANSMITS per kind whose transmission depends on its parameters.
    let transmitting = BsdfKind::ALL.into_iter().filter(|k| k.transmits_by_parameters()).map(|k| (k.transmits_override(), (f.transmitting_kinds & k.bit() != 0) as u32 as f64));
    let mut constants = vec![
        ("SAMPLER", key.method.sampler.constant() as f64),
        ("BSDF_SAMPLING", key.method.bsdf.constant() as f64),
        ("LIGHT_SAMPLING", key.method.lights.constant() as f64),
        ("LIGHT_SELECT", select.constant() as f64),
        ("TRIANGLE_SAMPLING", key.method.triangles.constant() as f64),
        ("MICROFACET_SAMPLING", key.method.microfacet.constant() as f64),
        ("LOBE_SELECTION", key.method.lobes.constant() as f64),
        ("ENV_SAMPLING", key.method.env_sampling.constant() as f64),
        ("NUM_SPHERES", f.num_spheres as f64),
        ("NUM_PLANES", f.num_planes as f64),
        ("NUM_DISKS", f.num_disks as f64),
        ("NUM_CYLINDERS", f.num_cylinders as f64),
        ("NUM_CURVE_SEGMENTS", f.num_curve_segments as f64),
        ("NUM_BSPLINE_SEGMENTS", f.num_bspline_segments as f64),
        ("NUM_SDF_GRIDS", f.num_sdf_grids as f64),
        ("NUM_TRIANGLES", f.num_triangles as f64),
        ("HAS_SHADING_NORMALS", f.has_shading_normals as u32 as f64),
        ("HAS_UVS", f.has_uvs as u32 as f64),
        ("HAS_MASKS", f.has_masks as u32 as f64),
        ("TEXTURED_OPACITY", f.textured_opacity as u32 as f64),
        ("TEXTURE_KINDS", f.texture_kinds as f64),
        ("MICROFACET_DISTRIBUTIONS", f.microfacet_distributions as f64),
        ("HAS_BACK_BSDFS", f.has_back_bsdfs as u32 as f64),
        ("HAS_BLENDS", f.has_blends as u32 as f64),
        ("HAS_EMISSION_TEXTURES", f.has_emission_textures as u32 as f64),
        ("ANISOTROPIC_ROUGHNESS", f.anisotropic_roughness as u32 as f64),
        ("HAS_NORMAL_MAPS", f.has_normal_maps as u32 as f64),
        ("HAS_BUMP_MAPS", f.has_bump_maps as u32 as f64),
        ("HAS_TANGENT_FRAMES", (f.anisotropic_roughness || f.has_normal_maps) as u32 as f64),
        ("THIN_LENS", f.thin_lens as u32 as f64),
        ("ORTHOGRAPHIC", f.orthographic as u32 as f64),
        ("HAS_LIGHT_TEXTURES", f.has_light_textures as u32 as f64),
        ("HIDE_EMITTERS", f.hide_emitters as u32 as f64),
        ("EMITTER_SKIPS", f.emitter_skips() as f64),
        ("RR_DEPTH", f.rr_depth as f64),
        ("TRAVERSAL_BUDGET", key.traversal_budget as f64),
        ("BSPLINE_UNROLLED", key.bspline_unrolled as u32 as f64),
        ("BVH_DEEP", key.deep_bvh as u32 as f64),
        ("NUM_OCCLUDING_PLANES", f.num_occluding_planes as f64),
        ("HAS_SPECULAR", f.has_specular as u32 as f64),
        ("HAS_ENVIRONMENT", f.has_environment as u32 as f64),
        ("HAS_ENVIRONMENT_MAP", f.has_environment_map as u32 as f64),
        ("LIGHT_INTERIORS_REACHABLE", f.light_interiors_reachable as u32 as f64),
        ("NUM_MEDIA", f.num_media as f64),
        ("CAMERA_MEDIUM", f.camera_medium as f64),
        ("MAX_NULL_COLLISIONS", f.max_null_collisions as f64),
        ("BSDF_TECHNIQUE", key.method.bsdf_technique.is_some() as u32 as f64),
        ("LIGHT_TECHNIQUE", key.method.light_technique.is_some() as u32 as f64),
        ("ENV_TECHNIQUE", key.method.env_technique.is_some() as u32 as f64),
    ];
    constants.extend(kinds);
    constants.extend(transmitting);
    // One TEXTURED_<KIND> per kind with texture slots.
    for k in BsdfKind::ALL.into_iter().filter(|k| !k.texture_slots().is_empty() || !k.scalar_texture_slots().is_empty()) {
        constants.push((k.textured_override(), f.textured_slots[k.constant() as usize] as f64));
    }
    // The small scene's distinct vertices and each triangle's corners among them.
    constants.extend(shaders::small_vertex_constants(&f.small_vertices));
    // One NUM_<KIND>_LIGHTS per emitter kind (NUM_LIGHTS is their sum, in the WGSL).
    constants.extend(EmitterKind::ALL.map(|k| (k.count_override(), f.lights_of(k) as f64)));
    constants
}

/// Loop back-edges of an SDF grid's normals at a hit (`sdf_grid_smooth_normal`'s eight cells
/// and three axes, and some to spare).
const SDF_NORMAL_LOOPS: u64 = 16;

/// Upper bounds on the loop back-edges one sample of the path tracer executes in one
/// invocation. Needed because llvmpipe/lavapipe ends every loop of an invocation once 65535
/// back-edges have run in total (`LP_MAX_TGSI_LOOP_ITERATIONS`), which silently cut frames
/// short.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LoopBound {
    /// Everything but BVH traversal: path vertices x (intersection, light and sampler loops).
    pub fixed: u64,
    /// Rays (camera, scattered and shadow rays) one sample traces at most.
    pub rays: u64,
    /// Traversal steps of one ray at worst, as the kernel's guard counts them (bvh.wgsl): every
    /// node visited once (a pass of the stackless traversal's inner loop) and climbed out of at
    /// most once; a climb up the parents started at most once per interior node (half the
    /// nodes), three steps for llvmpipe's passes of its loops; every triangle tested once, and
    /// three more per leaf for its loop (those costs measured: tests/bvh.rs). The stack's
    /// traversal takes fewer.
    pub steps_per_ray: u64,
}

impl LoopBound {
    /// The worst case of one sample.
    pub fn per_sample(&self) -> u64 {
        self.fixed + self.rays * self.steps_per_ray
    }

    /// The bound with the scene's shapes whose tests loop: each ray walks each SDF grid's cells
    /// (at most one step per cell plane it crosses, and one), runs the regula falsi steps in one
    /// of them (`intersect_sdf_grid`, quadrics/sdf_grid.wgsl) and the normals' loops at its hit;
    /// and passes over every B-spline segment's bounds (`bspline_candidates`, intersect.wgsl),
    /// then, unless `key` unrolls them, searches each segment's chords and runs two Newton solves
    /// (`intersect_bspline_curve`, quadrics/bspline_curve.wgsl).
    pub fn with_shape_loops(mut self, scene: &crate::scene::Scene, key: &PipelineKey) -> LoopBound {
        use crate::scene::quadrics::{BSPLINE_NEWTON_STEPS, BSPLINE_PIECES, REGULA_FALSI_STEPS};
        let grids: u64 = scene
            .quadrics
            .iter()
            .filter_map(|q| q.grid())
            .map(|g| g.res.iter().map(|&n| n as u64 - 1).sum::<u64>() + 1 + REGULA_FALSI_STEPS as u64 + SDF_NORMAL_LOOPS)
            .sum();
        // Each segment's search (its loops, where not unrolled), and the pass over every
        // segment's bounds before the searches (intersect.wgsl's bspline_candidates).
        let per_bspline = if key.bspline_unrolled { 0 } else { (BSPLINE_PIECES + 2 * BSPLINE_NEWTON_STEPS) as u64 } + 1;
        self.fixed += self.rays * (grids + key.features.num_bspline_segments as u64 * per_bspline);
        self
    }

    /// The bound with researchers' techniques that have loops: each call may run
    /// `TECHNIQUE_MAX_ITERATIONS` iterations before its guard stops it. Per vertex, a BSDF
    /// technique is called to sample and for the density there, and for the density of each
    /// light sample; a light technique to sample and for the density, for each light sample,
    /// and for the density of the emission the BSDF's ray finds.
    pub fn with_techniques(mut self, key: &PipelineKey, techniques: shaders::TechniqueFiles, max_depth: u32) -> LoopBound {
        let per_call = crate::scene::technique::TECHNIQUE_MAX_ITERATIONS as u64;
        let shadow_rays = match key.method.select {
            None | Some(LightSelect::All) => key.features.num_lights() as u64,
            Some(_) => 1,
        };
        let mut calls = 0;
        if techniques.bsdf.is_some_and(|t| t.loops > 0) {
            calls += 2 + shadow_rays;
        }
        if techniques.light.is_some_and(|t| t.loops > 0) {
            calls += 2 * shadow_rays + 1;
        }
        if techniques.env.is_some_and(|t| t.loops > 0) {
            calls += 2 + 1;
        }
        self.fixed += max_depth as u64 * calls * per_call;
        self
    }
}

/// The loop bound of one sample of `key` at `max_depth` over a BVH of `bvh_nodes` nodes of
/// which `bvh_leaves` are leaves.
pub fn loop_iterations_per_sample(key: &PipelineKey, max_depth: u32, bvh_nodes: u64, bvh_leaves: u64) -> LoopBound {
    use crate::method::Sampler;
    let f = &key.features;
    // Quadrics are tested in loops of their own, as spheres are.
    let (s, p, l) = ((f.num_spheres + f.num_disks + f.num_cylinders + f.num_curve_segments + f.num_bspline_segments + f.num_sdf_grids) as u64, f.num_planes as u64, f.num_lights() as u64);
    // Iterations of one sample_1d call: Sobol' has no loop; Halton reverses at most 21 + 1
    // digits (base 3); Owen-scrambled Halton expands ~24 bits of digits, each with a few
    // rejection rounds of the hashed permutation.
    let per_dim: u64 = match key.method.sampler {
        Sampler::Independent | Sampler::Sobol => 0,
        Sampler::Halton => 44,
        Sampler::HaltonScrambled => 160,
    };
    // Shadow rays and light dimensions per vertex: every light, or one.
    let (shadow_rays, light_dims) = match key.method.select {
        None | Some(LightSelect::All) => (l, 2 * l),
        Some(_) => (l.min(1), 3),
    };
    // Drawing from an environment map's distribution: two bisections, at most 32 steps each.
    let env_search = if f.has_environment_map && key.method.environment { 64 } else { 0 };
    let per_vertex = 1 + s + p + shadow_rays * (1 + s + p) + (3 + light_dims) * per_dim + env_search;
    // Under hide_emitters, camera rays passing through area emitters: one loop iteration and
    // one more ray each.
    let skips = f.emitter_skips() as u64;
    if f.num_media > 0 {
        // The volumetric loop (volpath.wgsl): its segments, each shadow ray up to
        // MAX_SHADOW_CROSSINGS intersections, each a pass of the intersection loops.
        let segments = crate::scene::media::max_segments(max_depth) as u64;
        let per_shadow_ray = crate::scene::media::MAX_SHADOW_CROSSINGS as u64;
        // Tracking in heterogeneous media (medium.wgsl): a path segment's delta tracking, the
        // box's three slabs, each null collision's pass with its σ_t lookup (a grid's two
        // z-planes) and the albedo's lookup where light scatters; a shadow ray's ratio
        // tracking, the slabs at each crossing and its collisions, one budget for all.
        let n = f.max_null_collisions as u64;
        let (segment_tracking, shadow_tracking) = if n > 0 { (3 + 3 * n + 2, per_shadow_ray * 3 + 3 * n) } else { (0, 0) };
        let per_segment = 1 + s + p + shadow_rays * (per_shadow_ray * (1 + s + p) + shadow_tracking) + (5 + light_dims) * per_dim + env_search + segment_tracking + skips * (1 + s + p);
        let fixed = 1 + 2 * per_dim + segments * per_segment;
        let rays = 1 + segments * (1 + shadow_rays * per_shadow_ray + skips);
        let steps_per_ray = if f.num_triangles > 0 { 4 * bvh_nodes + 3 * bvh_leaves + f.num_triangles as u64 } else { 0 };
        return LoopBound { fixed, rays, steps_per_ray };
    }
    let fixed = 1 + 2 * per_dim + max_depth as u64 * per_vertex + skips * (1 + s + p);
    let rays = 1 + max_depth as u64 * (1 + shadow_rays) + skips;
    let steps_per_ray = if f.num_triangles > 0 { 4 * bvh_nodes + 3 * bvh_leaves + f.num_triangles as u64 } else { 0 };
    LoopBound { fixed, rays, steps_per_ray }
}

/// What the kernel is tuned to by the kind of adapter (measured on each), beside the method and
/// the scene: both choices leave every hit, and so the image, the same.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AdapterTuning {
    /// The most triangles a scene may have for the kernel to test every one in turn (unrolled,
    /// from a uniform buffer) rather than traverse the BVH; at most
    /// `accel::BRUTE_FORCE_TRIANGLES`.
    pub brute_force_limit: u32,
    /// The BVH traversal keeps no stack (`BVH_STACKLESS`, bvh.wgsl).
    pub stackless_traversal: bool,
    /// The triangle test's edge functions are computed in one order for both triangles of an
    /// edge (`ORDERED_EDGES`, bvh.wgsl): watertight where the driver fuses multiply-adds.
    pub ordered_edges: bool,
    /// The scene's spheres, planes and quadrics are copied into registers at kernel entry
    /// where each table is small (`SCENE_IN_REGISTERS`, src/shaders/generated.rs).
    pub scene_in_registers: bool,
    /// Next event estimation towards every light visits each at a constant index, not in a
    /// loop, where a scene has at most `shaders::UNROLLED_LIGHTS` (`LIGHTS_UNROLLED`,
    /// src/shaders/generated.rs).
    pub lights_unrolled: bool,
}

impl AdapterTuning {
    /// The tuning of an adapter of `device_type`.
    ///
    /// CPU adapters (lavapipe, 2026-12-03/04, `pathlab bench ... --methods mis`): small scenes
    /// triangle by triangle (the Cornell box, 36 triangles, 1.32 M samples/s against 0.56
    /// through the BVH) and the stackless traversal (80-triangle icosphere 6.27 -> 8.15 M
    /// rays/s, Veach's scene 4.99 -> 7.37).
    ///
    /// GPUs (NVIDIA H200, 2026-12-04, 1024x1024): the BVH for every scene (the Cornell box 74 M
    /// samples/s unrolled, each invocation's copy of the triangles in local memory, 560
    /// through the BVH) and the stack (80-triangle icosphere 3748 M samples/s against 3250
    /// stackless, 1.3 M triangles 642 against 446).
    ///
    /// Spheres, planes and quadrics in registers on CPU adapters only (`SCENE_IN_REGISTERS`,
    /// 2026-12-07): lavapipe reads a uniform buffer inside the bounce loop lane by lane, and the
    /// study scene's kernel took 364.9 M instructions with the reads, 226.7 M with the copies
    /// (callgrind, `pathlab render assets/scenes/study.toml --method mis --spp 64 --width 64
    /// --height 64 --seed 3`; the quadrics fixture 470.1 M -> 389.8 M at 16 spp); GPUs
    /// broadcast uniform reads from their constant caches, where the copies would only take
    /// registers.
    ///
    /// Each light at a constant index on CPU adapters only (`LIGHTS_UNROLLED`, 2026-12-07):
    /// lavapipe's NIR left the loop over the lights rolled, so every light's data and kind were
    /// chosen at run time; the study scene's kernel took 84.1 M instructions looped and 73.8 M
    /// unrolled, Veach's 326.1 M and 270.3 M (`scripts/kernel_instructions.sh`), and the study
    /// scene ran 89-91 M rays/s looped, 109-112 unrolled (`scripts/compare_builds.sh`, 1024x512,
    /// 4 rounds). GPUs keep the loop (no GPU was lent to measure the copies' code size there).
    ///
    /// Ordered edge functions on GPUs only: there the plain ones let rays through shared edges
    /// (the H200 fuses multiply-adds); lavapipe does not fuse, and ordering would cost its
    /// Cornell box 14% more kernel instructions.
    pub fn for_device(device_type: wgpu::DeviceType) -> AdapterTuning {
        let cpu = device_type == wgpu::DeviceType::Cpu;
        AdapterTuning {
            brute_force_limit: if cpu { crate::accel::BRUTE_FORCE_TRIANGLES } else { 0 },
            stackless_traversal: cpu,
            ordered_edges: !cpu,
            scene_in_registers: cpu,
            lights_unrolled: cpu,
        }
    }

    /// The `override` constants it sets.
    pub fn constants(&self) -> Vec<(&'static str, f64)> {
        vec![
            ("BVH_STACKLESS", self.stackless_traversal as u32 as f64),
            ("ORDERED_EDGES", self.ordered_edges as u32 as f64),
            ("SCENE_IN_REGISTERS", self.scene_in_registers as u32 as f64),
            ("LIGHTS_UNROLLED", self.lights_unrolled as u32 as f64),
        ]
    }
}

/// Time spent creating one pipeline (shader specialisation and driver compilation).
#[derive(Debug, Clone, Copy)]
pub struct PipelineStats {
    pub compile_time: Duration,
}

/// The researchers' techniques a module holds: their files' SHA-256 by kind.
type TechniqueKey = (Option<String>, Option<String>, Option<String>);

/// Pipelines a `PathTracerPipelines` keeps (the most recently used): every method of a study
/// or of a test of one scene; lavapipe holds 20 MB (the Cornell box) to 600 MB (a heterogeneous
/// medium) a pipeline.
const CACHED_PIPELINES: usize = 48;

/// Parsed path-tracer modules it keeps (one per unrolled triangle count and set of techniques).
const CACHED_MODULES: usize = 4;

/// The path tracer's shader modules, bind group layout and a cache of specialised pipelines.
pub struct PathTracerPipelines {
    /// One parsed module per count its small-scene triangle tests are unrolled to
    /// (`shaders::unrolled_triangles`) and researchers' techniques (their SHA-256s), parsed on
    /// first use and specialised per pipeline (`shaders::specialise`).
    modules: Mutex<Recent<(u32, TechniqueKey), Arc<ParsedModule>>>,
    /// The tuning to the adapter's kind.
    tuning: AdapterTuning,
    /// The Halton bases, bound at `bindings::HALTON_PRIMES`.
    pub halton_primes: wgpu::Buffer,
    pub bind_group_layout: wgpu::BindGroupLayout,
    layout: wgpu::PipelineLayout,
    /// The most recently used pipelines (`CACHED_PIPELINES`).
    cache: Mutex<Recent<(PipelineKey, TechniqueKey), (Arc<wgpu::ComputePipeline>, PipelineStats)>>,
}

impl PathTracerPipelines {
    /// The pipelines of `gpu`, tuned to its kind of adapter (`AdapterTuning::for_device`).
    pub fn new(gpu: &super::Gpu) -> PathTracerPipelines {
        Self::with_tuning(&gpu.device, AdapterTuning::for_device(gpu.info.device_type))
    }

    /// The pipelines of `device` with `tuning` (tests compare the tunings on one adapter).
    pub fn with_tuning(device: &wgpu::Device, tuning: AdapterTuning) -> PathTracerPipelines {
        let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("path tracer"),
            entries: &bindings::layout_entries(&bindings::PATH_TRACER),
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("path tracer"),
            bind_group_layouts: &[Some(&bind_group_layout)],
            immediate_size: 0,
        });
        let halton_primes = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("halton primes"),
            contents: &shaders::halton_primes_bytes(),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        PathTracerPipelines { modules: Mutex::new(Recent::new(CACHED_MODULES)), tuning, halton_primes, bind_group_layout, layout, cache: Mutex::new(Recent::new(CACHED_PIPELINES)) }
    }

    /// Drops all but the `keep` most recently used pipelines (a long-lived process between
    /// jobs: the test suite between tests). Renderers keep the pipelines they hold.
    pub fn retain_recent(&self, keep: usize) {
        self.cache.lock().unwrap_or_else(|e| e.into_inner()).truncate(keep);
    }

    /// The pipeline for `key` with `techniques` (those its method names), compiled on first
    /// use (or again, once `CACHED_PIPELINES` others have been used since).
    pub fn get(&self, device: &wgpu::Device, key: PipelineKey, techniques: shaders::TechniqueFiles) -> (Arc<wgpu::ComputePipeline>, PipelineStats) {
        let mut cache = self.cache.lock().unwrap_or_else(|e| e.into_inner());
        let technique_key = techniques.key();
        if let Some((p, s)) = cache.get(&(key, technique_key.clone())) {
            return (p.clone(), *s);
        }
        let mut constants = pipeline_constants(&key);
        constants.extend(self.tuning.constants());
        let start = Instant::now();
        let unrolled = shaders::unrolled_triangles(key.features.num_triangles, self.tuning.brute_force_limit);
        let parsed = {
            let mut modules = self.modules.lock().unwrap_or_else(|e| e.into_inner());
            let module_key = (unrolled, technique_key.clone());
            match modules.get(&module_key) {
                Some(parsed) => parsed.clone(),
                None => {
                    let source = shaders::path_tracer_source_with(unrolled, techniques);
                    // The assembled kernel and validated techniques: an error here is pathlab's.
                    let parsed = Arc::new(specialise::parse(&source).unwrap_or_else(|e| panic!("the path tracer does not parse:\n{e}")));
                    modules.insert(module_key, parsed.clone());
                    parsed
                }
            }
        };
        // The kernel reduced to what this key's constants reach: the driver compiles no more.
        let specialised = specialise::specialise(&parsed, shaders::PATH_TRACER_ENTRY, &constants)
            .unwrap_or_else(|e| panic!("the path tracer does not specialise to {key:?}:\n{e}"));
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("path tracer"),
            source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(specialised)),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("path tracer"),
            layout: Some(&self.layout),
            module: &module,
            entry_point: Some(shaders::PATH_TRACER_ENTRY),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &[],
                zero_initialize_workgroup_memory: false,
            },
            cache: None,
        });
        let stats = PipelineStats { compile_time: start.elapsed() };
        let pipeline = Arc::new(pipeline);
        cache.insert((key, technique_key), (pipeline.clone(), stats));
        (pipeline, stats)
    }
}
