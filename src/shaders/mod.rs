//! Assembly of the WGSL sources in `shaders/` into complete modules, and their validation
//! with naga (the same front end wgpu uses).
//!
//! The files are concatenated in dependency order; WGSL has no include mechanism, so this is
//! the one place that knows the order. Everything the host and the kernels must agree on is
//! generated in front of them from the Rust definitions (`generated`): capacities, the values
//! of the `override` choices, binding numbers. Shared struct layouts are checked against naga's
//! reflection of the module (`tests/shader_layouts.rs`).

pub mod bindings;
pub mod flags;
mod generated;
pub mod specialise;

use std::fmt::Write as _;

use crate::method::TechniqueKind;
use crate::scene::{Technique, TechniqueError};

pub use generated::{bsdf_dispatch, bspline_unrolled, emitter_dispatch, generated_constants, light_counts, lights_unrolled, scene_registers, small_corner_names, small_first_use_names, small_triangle_names, small_triangle_tests, small_vertex_constants, REGISTER_ENTRIES, UNROLLED_LIGHTS};

/// Number of Halton dimensions with their own prime base; later dimensions fall back to the
/// independent sampler. A multiple of 4: the primes are packed four to a `vec4u`.
pub const HALTON_DIMENSIONS: usize = 256;

/// The Halton bases as bound at `HALTON_PRIMES_BINDING`: `primes(HALTON_DIMENSIONS)`, as the
/// bytes of the uniform array of `vec4u`.
pub fn halton_primes_bytes() -> Vec<u8> {
    bytemuck::cast_slice(&primes(HALTON_DIMENSIONS)).to_vec()
}

/// WGSL files, by concern, in the order they must be concatenated.
pub mod files {
    pub const COMMON: (&str, &str) = ("common.wgsl", include_str!("../../shaders/common.wgsl"));
    pub const SAMPLER: (&str, &str) = ("sampler.wgsl", include_str!("../../shaders/sampler.wgsl"));
    pub const WARP: (&str, &str) = ("warp.wgsl", include_str!("../../shaders/warp.wgsl"));
    /// Phase functions of participating media (sampled and evaluated like BSDFs).
    pub const PHASE: (&str, &str) = ("phase.wgsl", include_str!("../../shaders/phase.wgsl"));
    /// Homogeneous media: records, free-flight sampling, transmittance, boundaries.
    pub const MEDIUM: (&str, &str) = ("medium.wgsl", include_str!("../../shaders/medium.wgsl"));
    /// The path tracer's volumetric loop (scenes with media).
    pub const VOLPATH: (&str, &str) = ("volpath.wgsl", include_str!("../../shaders/volpath.wgsl"));
    pub const SPHERICAL_TRIANGLE: (&str, &str) = ("spherical_triangle.wgsl", include_str!("../../shaders/spherical_triangle.wgsl"));
    pub const LIGHT_TABLE: (&str, &str) = ("light_table.wgsl", include_str!("../../shaders/light_table.wgsl"));
    pub const BVH: (&str, &str) = ("bvh.wgsl", include_str!("../../shaders/bvh.wgsl"));
    pub const MICROFACET: (&str, &str) = ("microfacet.wgsl", include_str!("../../shaders/microfacet.wgsl"));
    pub const FRESNEL: (&str, &str) = ("fresnel.wgsl", include_str!("../../shaders/fresnel.wgsl"));
    pub const BSDF: (&str, &str) = ("bsdf.wgsl", include_str!("../../shaders/bsdf.wgsl"));
    pub const TEXTURE: (&str, &str) = ("texture.wgsl", include_str!("../../shaders/texture.wgsl"));
    /// One file per kind of the BSDF registry (`scene::BsdfKind`), in its order.
    pub const BSDF_KINDS: [(&str, &str); 11] = [
        ("bsdfs/phong.wgsl", include_str!("../../shaders/bsdfs/phong.wgsl")),
        ("bsdfs/conductor.wgsl", include_str!("../../shaders/bsdfs/conductor.wgsl")),
        ("bsdfs/rough_conductor.wgsl", include_str!("../../shaders/bsdfs/rough_conductor.wgsl")),
        ("bsdfs/dielectric.wgsl", include_str!("../../shaders/bsdfs/dielectric.wgsl")),
        ("bsdfs/plastic.wgsl", include_str!("../../shaders/bsdfs/plastic.wgsl")),
        ("bsdfs/rough_dielectric.wgsl", include_str!("../../shaders/bsdfs/rough_dielectric.wgsl")),
        ("bsdfs/thin_dielectric.wgsl", include_str!("../../shaders/bsdfs/thin_dielectric.wgsl")),
        ("bsdfs/rough_plastic.wgsl", include_str!("../../shaders/bsdfs/rough_plastic.wgsl")),
        ("bsdfs/principled.wgsl", include_str!("../../shaders/bsdfs/principled.wgsl")),
        ("bsdfs/polarized_plastic.wgsl", include_str!("../../shaders/bsdfs/polarized_plastic.wgsl")),
        ("bsdfs/principled_thin.wgsl", include_str!("../../shaders/bsdfs/principled_thin.wgsl")),
    ];
    /// Mitsuba's mask around any kind (`scene::Opacity`): after the kinds.
    pub const MASK: (&str, &str) = ("bsdfs/mask.wgsl", include_str!("../../shaders/bsdfs/mask.wgsl"));
    /// Mitsuba's normalmap around any reflecting kind (`scene::NormalMap`): after the mask.
    pub const NORMAL_MAP: (&str, &str) = ("bsdfs/normal_map.wgsl", include_str!("../../shaders/bsdfs/normal_map.wgsl"));
    /// Mitsuba's bumpmap around any reflecting kind (`scene::BumpMap`): after the normal map,
    /// whose perturbed frame it shares.
    pub const BUMP_MAP: (&str, &str) = ("bsdfs/bump_map.wgsl", include_str!("../../shaders/bsdfs/bump_map.wgsl"));
    pub const LIGHTS: (&str, &str) = ("lights.wgsl", include_str!("../../shaders/lights.wgsl"));
    /// The seam for a researcher's technique (its contract and wrappers); the technique files,
    /// or these stand-ins where none is loaded, follow it.
    pub const TECHNIQUE: (&str, &str) = ("technique.wgsl", include_str!("../../shaders/technique.wgsl"));
    pub const NO_BSDF_TECHNIQUE: (&str, &str) = ("techniques/none_bsdf.wgsl", include_str!("../../shaders/techniques/none_bsdf.wgsl"));
    pub const NO_MICROFACET_TECHNIQUE: (&str, &str) = ("techniques/none_microfacet.wgsl", include_str!("../../shaders/techniques/none_microfacet.wgsl"));
    pub const NO_MICROFACET_UV_TECHNIQUE: (&str, &str) =
        ("techniques/none_microfacet_uv.wgsl", include_str!("../../shaders/techniques/none_microfacet_uv.wgsl"));
    pub const NO_LIGHT_TECHNIQUE: (&str, &str) = ("techniques/none_light.wgsl", include_str!("../../shaders/techniques/none_light.wgsl"));
    pub const NO_TRIANGLE_LIGHT_TECHNIQUE: (&str, &str) =
        ("techniques/none_triangle_light.wgsl", include_str!("../../shaders/techniques/none_triangle_light.wgsl"));
    pub const NO_DISK_LIGHT_TECHNIQUE: (&str, &str) = ("techniques/none_disk_light.wgsl", include_str!("../../shaders/techniques/none_disk_light.wgsl"));
    pub const NO_CYLINDER_LIGHT_TECHNIQUE: (&str, &str) =
        ("techniques/none_cylinder_light.wgsl", include_str!("../../shaders/techniques/none_cylinder_light.wgsl"));
    pub const NO_ENV_TECHNIQUE: (&str, &str) = ("techniques/none_env.wgsl", include_str!("../../shaders/techniques/none_env.wgsl"));
    pub const EMITTER: (&str, &str) = ("emitter.wgsl", include_str!("../../shaders/emitter.wgsl"));
    /// One file per kind of the emitter registry (`scene::EmitterKind`), in its order.
    pub const EMITTER_KINDS: [(&str, &str); 9] = [
        ("emitters/sphere.wgsl", include_str!("../../shaders/emitters/sphere.wgsl")),
        ("emitters/triangle.wgsl", include_str!("../../shaders/emitters/triangle.wgsl")),
        ("emitters/disk.wgsl", include_str!("../../shaders/emitters/disk.wgsl")),
        ("emitters/cylinder.wgsl", include_str!("../../shaders/emitters/cylinder.wgsl")),
        ("emitters/point.wgsl", include_str!("../../shaders/emitters/point.wgsl")),
        ("emitters/spot.wgsl", include_str!("../../shaders/emitters/spot.wgsl")),
        ("emitters/directional.wgsl", include_str!("../../shaders/emitters/directional.wgsl")),
        ("emitters/projector.wgsl", include_str!("../../shaders/emitters/projector.wgsl")),
        ("emitters/environment.wgsl", include_str!("../../shaders/emitters/environment.wgsl")),
    ];
    pub const SCENE: (&str, &str) = ("scene.wgsl", include_str!("../../shaders/scene.wgsl"));
    /// The quadrics' record, then their intersection, normals, uvs and sampling, one file per
    /// kind (`QuadricKind`).
    pub const QUADRIC: (&str, &str) = ("quadrics/quadric.wgsl", include_str!("../../shaders/quadrics/quadric.wgsl"));
    pub const DISK: (&str, &str) = ("quadrics/disk.wgsl", include_str!("../../shaders/quadrics/disk.wgsl"));
    pub const CYLINDER: (&str, &str) = ("quadrics/cylinder.wgsl", include_str!("../../shaders/quadrics/cylinder.wgsl"));
    pub const LINEAR_CURVE: (&str, &str) = ("quadrics/linear_curve.wgsl", include_str!("../../shaders/quadrics/linear_curve.wgsl"));
    pub const BSPLINE_CURVE: (&str, &str) = ("quadrics/bspline_curve.wgsl", include_str!("../../shaders/quadrics/bspline_curve.wgsl"));
    pub const SDF_GRID: (&str, &str) = ("quadrics/sdf_grid.wgsl", include_str!("../../shaders/quadrics/sdf_grid.wgsl"));
    pub const INTERSECT: (&str, &str) = ("intersect.wgsl", include_str!("../../shaders/intersect.wgsl"));
    pub const ACCUM_PIXEL: (&str, &str) = ("accum_pixel.wgsl", include_str!("../../shaders/accum_pixel.wgsl"));
    pub const ACCUMULATE: (&str, &str) = ("accumulate.wgsl", include_str!("../../shaders/accumulate.wgsl"));
    pub const DISPLAY: (&str, &str) = ("display.wgsl", include_str!("../../shaders/display.wgsl"));
    pub const INTEGRATOR: (&str, &str) = ("integrator.wgsl", include_str!("../../shaders/integrator.wgsl"));
}

/// The sampling library without scene bindings: samplers, warps, BSDF and light sampling. Its
/// one binding is the BSDFs' data (`bindings::BSDF_DATA`), which `KernelRun` fills with a
/// placeholder where a test kernel gives none. Test kernels append their own bindings and entry
/// points to this.
pub const LIBRARY: [(&str, &str); 15] = [
    files::COMMON,
    files::SAMPLER,
    files::WARP,
    files::PHASE,
    files::SPHERICAL_TRIANGLE,
    files::MICROFACET,
    files::FRESNEL,
    files::BSDF,
    files::TEXTURE,
    files::LIGHTS,
    files::QUADRIC,
    files::DISK,
    files::CYLINDER,
    files::LINEAR_CURVE,
    files::TECHNIQUE,
];

/// Everything the path-tracing kernel (`render_main`) needs.
pub const PATH_TRACER: [(&str, &str); 27] = [
    files::COMMON,
    files::SAMPLER,
    files::WARP,
    files::PHASE,
    files::SPHERICAL_TRIANGLE,
    files::MICROFACET,
    files::FRESNEL,
    files::BSDF,
    files::TEXTURE,
    files::LIGHTS,
    files::QUADRIC,
    files::DISK,
    files::CYLINDER,
    files::LINEAR_CURVE,
    files::BSPLINE_CURVE,
    files::SDF_GRID,
    files::TECHNIQUE,
    files::LIGHT_TABLE,
    files::SCENE,
    files::MEDIUM,
    files::BVH,
    files::INTERSECT,
    files::EMITTER,
    files::ACCUM_PIXEL,
    files::ACCUMULATE,
    files::INTEGRATOR,
    files::VOLPATH,
];

/// The viewer's display pass (`display_main`): accumulator to shown texture.
pub const DISPLAY: [(&str, &str); 2] = [files::ACCUM_PIXEL, files::DISPLAY];

/// Entry point of the display pass.
pub const DISPLAY_ENTRY: &str = "display_main";

/// The display pass module.
pub fn display_source() -> String {
    assemble(&DISPLAY, "")
}

/// Entry point of the path tracer.
pub const PATH_TRACER_ENTRY: &str = "render_main";

/// Concatenates generated constants and `parts` (then `extra`, e.g. a test kernel) into one
/// WGSL module, each file introduced by a comment naming it. Where `parts` hold the BSDFs' or
/// the emitters' common file, every kind's file (for BSDFs, then the mask's) and the generated dispatch follow it; after
/// bvh.wgsl, the small scenes' triangle tests for any count up to `BRUTE_FORCE_TRIANGLES`;
/// after technique.wgsl, the stand-ins for techniques (none loaded).
pub fn assemble(parts: &[(&str, &str)], extra: &str) -> String {
    assemble_unrolled(parts, extra, crate::accel::BRUTE_FORCE_TRIANGLES)
}

/// The researchers' techniques a module is built with: at most one per kind (else the
/// kind's stand-in, `files::NO_*_TECHNIQUE`).
#[derive(Debug, Clone, Copy, Default)]
pub struct TechniqueFiles<'a> {
    pub bsdf: Option<&'a Technique>,
    pub light: Option<&'a Technique>,
    pub env: Option<&'a Technique>,
}

impl<'a> TechniqueFiles<'a> {
    /// The techniques `method` uses, from those loaded; an error names one that is not.
    pub fn of(method: &crate::method::Method, loaded: &'a [Technique]) -> Result<TechniqueFiles<'a>, TechniqueError> {
        let find = |kind: TechniqueKind, name: Option<crate::method::TechniqueName>| -> Result<Option<&'a Technique>, TechniqueError> {
            let Some(name) = name else { return Ok(None) };
            loaded
                .iter()
                .find(|t| t.kind == kind && t.name == name)
                .map(Some)
                .ok_or(TechniqueError::NotLoaded { kind, name: name.to_string() })
        };
        Ok(TechniqueFiles {
            bsdf: find(TechniqueKind::Bsdf, method.bsdf_technique)?,
            light: find(TechniqueKind::Light, method.light_technique)?,
            env: find(TechniqueKind::Env, method.env_technique)?,
        })
    }

    /// One technique in its kind's place.
    pub fn only(t: &'a Technique) -> TechniqueFiles<'a> {
        match t.kind {
            TechniqueKind::Bsdf => TechniqueFiles { bsdf: Some(t), ..Default::default() },
            TechniqueKind::Light => TechniqueFiles { light: Some(t), ..Default::default() },
            TechniqueKind::Env => TechniqueFiles { env: Some(t), ..Default::default() },
        }
    }

    /// What identifies the module they make (their SHA-256s).
    pub fn key(&self) -> (Option<String>, Option<String>, Option<String>) {
        (self.bsdf.map(|t| t.sha256.clone()), self.light.map(|t| t.sha256.clone()), self.env.map(|t| t.sha256.clone()))
    }

    /// The files, by kind.
    pub fn all(&self) -> impl Iterator<Item = &'a Technique> {
        [self.bsdf, self.light, self.env].into_iter().flatten()
    }
}

/// The number of triangle tests the small scenes' code is unrolled to for a scene of
/// `num_triangles` where scenes of at most `limit` triangles are tested triangle by triangle
/// (`gpu::AdapterTuning::brute_force_limit`, at most `BRUTE_FORCE_TRIANGLES`): its own count where
/// it is, else none (a larger scene traverses the BVH, and an empty one tests nothing).
pub fn unrolled_triangles(num_triangles: u32, limit: u32) -> u32 {
    if num_triangles <= limit.min(crate::accel::BRUTE_FORCE_TRIANGLES) { num_triangles } else { 0 }
}

/// `assemble`, with the small scenes' triangle tests unrolled to `small_triangles` steps: the
/// module then serves scenes of exactly that many triangles, or of more than
/// `BRUTE_FORCE_TRIANGLES` (see `unrolled_triangles`).
pub fn assemble_unrolled(parts: &[(&str, &str)], extra: &str, small_triangles: u32) -> String {
    assemble_with(parts, extra, small_triangles, TechniqueFiles::default())
}

/// `assemble_unrolled`, with researchers' techniques (their guarded source) after
/// technique.wgsl.
pub fn assemble_with(parts: &[(&str, &str)], extra: &str, small_triangles: u32, techniques: TechniqueFiles) -> String {
    let mut source = generated_constants();
    let push = |source: &mut String, (name, text): (&str, &str)| {
        let _ = writeln!(source, "\n// ===== shaders/{name} =====");
        source.push_str(text);
    };
    for &part in parts {
        push(&mut source, part);
        if part == files::BSDF {
            files::BSDF_KINDS.into_iter().for_each(|kind| push(&mut source, kind));
            push(&mut source, files::MASK);
            push(&mut source, files::NORMAL_MAP);
            push(&mut source, files::BUMP_MAP);
            source.push_str("\n// ===== generated by src/shaders/generated.rs: the BSDF dispatch =====\n");
            source.push_str(&bsdf_dispatch());
        }
        if part == files::BVH {
            source.push_str("\n// ===== generated by src/shaders/generated.rs: the small scenes' triangle tests =====\n");
            source.push_str(&small_triangle_tests(small_triangles));
        }
        if part == files::BSPLINE_CURVE {
            source.push_str("\n// ===== generated by src/shaders/generated.rs: a B-spline segment's search, unrolled =====\n");
            source.push_str(&bspline_unrolled());
        }
        if part == files::SCENE {
            source.push_str("\n// ===== generated by src/shaders/generated.rs: the scene's tables in registers =====\n");
            source.push_str(&scene_registers());
        }
        if part == files::LIGHT_TABLE {
            source.push_str("\n// ===== generated by src/shaders/generated.rs: the lights' counts =====\n");
            source.push_str(&light_counts());
        }
        let each_light = lights_unrolled(part);
        if !each_light.is_empty() {
            source.push_str("\n// ===== generated by src/shaders/generated.rs: next event estimation's visits of every light =====\n");
            source.push_str(&each_light);
        }
        if part == files::TECHNIQUE {
            for (technique, none) in [(techniques.bsdf, files::NO_BSDF_TECHNIQUE), (techniques.light, files::NO_LIGHT_TECHNIQUE), (techniques.env, files::NO_ENV_TECHNIQUE)] {
                match technique {
                    Some(t) => {
                        let _ = writeln!(source, "\n// ===== {} technique {} ({}) =====", t.kind, t.name, t.path.display());
                        source.push_str(&t.guarded);
                        source.push('\n');
                    }
                    None => push(&mut source, none),
                }
            }
            // A bsdf technique samples the materials, a light technique the shapes, whose
            // functions it defines; the others' are stood in for (never called).
            let targets = techniques.bsdf.map(Technique::bsdf_targets).unwrap_or_default();
            if techniques.bsdf.is_some() && !targets.phong {
                push(&mut source, files::NO_BSDF_TECHNIQUE);
            }
            if !targets.microfacet {
                push(&mut source, files::NO_MICROFACET_TECHNIQUE);
            }
            if !targets.microfacet_uv {
                push(&mut source, files::NO_MICROFACET_UV_TECHNIQUE);
            }
            let _ = writeln!(
                source,
                "\n// ===== generated by src/shaders/mod.rs: what the bsdf technique samples (Technique::bsdf_targets) =====\n\
                 const BSDF_TECHNIQUE_PHONG: bool = {};\nconst BSDF_TECHNIQUE_MICROFACET: bool = {};\nconst BSDF_TECHNIQUE_MICROFACET_UV: bool = {};",
                targets.phong,
                targets.samples_microfacet(),
                targets.microfacet_uv
            );
            let shapes = techniques.light.map(Technique::light_shapes).unwrap_or_default();
            if techniques.light.is_some() && !shapes.spheres {
                push(&mut source, files::NO_LIGHT_TECHNIQUE);
            }
            for (samples, none) in [
                (shapes.triangles, files::NO_TRIANGLE_LIGHT_TECHNIQUE),
                (shapes.disks, files::NO_DISK_LIGHT_TECHNIQUE),
                (shapes.cylinders, files::NO_CYLINDER_LIGHT_TECHNIQUE),
            ] {
                if !samples {
                    push(&mut source, none);
                }
            }
            let _ = writeln!(
                source,
                "\n// ===== generated by src/shaders/mod.rs: the shapes the light technique samples (Technique::light_shapes) =====\n\
                 const LIGHT_TECHNIQUE_SPHERES: bool = {};\nconst LIGHT_TECHNIQUE_TRIANGLES: bool = {};\n\
                 const LIGHT_TECHNIQUE_DISKS: bool = {};\nconst LIGHT_TECHNIQUE_CYLINDERS: bool = {};",
                shapes.spheres, shapes.triangles, shapes.disks, shapes.cylinders
            );
        }
        if part == files::EMITTER {
            files::EMITTER_KINDS.into_iter().for_each(|kind| push(&mut source, kind));
            source.push_str("\n// ===== generated by src/shaders/generated.rs: the emitter dispatch =====\n");
            source.push_str(&emitter_dispatch());
        }
    }
    if !extra.is_empty() {
        source.push_str("\n// ===== kernel =====\n");
        source.push_str(extra);
    }
    source
}

/// The complete path-tracing module, for scenes of any number of triangles (validation and
/// reflection use it).
pub fn path_tracer_source() -> String {
    assemble(&PATH_TRACER, "")
}

/// The path-tracing module with its small-scene tests unrolled to `unrolled` steps
/// (`unrolled_triangles`): it serves scenes of exactly that many triangles by testing each, and
/// larger ones through the BVH.
pub fn path_tracer_source_for(unrolled: u32) -> String {
    assemble_unrolled(&PATH_TRACER, "", unrolled)
}

/// `path_tracer_source_for`, with researchers' techniques.
pub fn path_tracer_source_with(unrolled: u32, techniques: TechniqueFiles) -> String {
    assemble_with(&PATH_TRACER, "", unrolled, techniques)
}

/// Validates a technique file with naga, as part of the sampling library: errors point at the
/// file's own line and column; a file that does not define its kind's functions with the
/// contract's signatures (shaders/technique.wgsl), or keeps state (`var<private>`, bindings,
/// `override`s), is refused naming what is missing or not allowed.
pub fn validate_technique(t: &Technique) -> Result<(), TechniqueError> {
    // The file as written (not guarded), so that columns are the file's.
    let plain = Technique { guarded: t.source.clone(), ..t.clone() };
    // In the whole path tracer: an environment technique reads the map's functions.
    let source = assemble_with(&PATH_TRACER, "", crate::accel::BRUTE_FORCE_TRIANGLES, TechniqueFiles::only(&plain));
    let header = format!("\n// ===== {} technique {} ({}) =====\n", t.kind, t.name, t.path.display());
    let start = source.find(&header).expect("the technique is in the module") + header.len();
    let end = start + t.source.len();
    let file = t.path.display();
    // (line, column) in the technique's file of a byte offset of the module, if it is in it.
    let locate = |offset: usize| -> Option<(usize, usize)> {
        if offset < start || offset > end {
            return None;
        }
        let before = &source[start..offset];
        let line = before.matches('\n').count() + 1;
        let column = before.rfind('\n').map_or(before.len(), |n| before.len() - n - 1) + 1;
        Some((line, column))
    };
    let contract = match t.kind {
        TechniqueKind::Bsdf => {
            "for Phong materials fn sample_bsdf_technique(wo: vec3f, m: PhongMaterial, u: vec2f, u_lobe: f32) -> vec3f and fn pdf_bsdf_technique(wo: vec3f, m: PhongMaterial, wi: vec3f) -> f32, \
             for microfacet normals fn sample_microfacet_technique(wo: vec3f, alpha: f32, distribution: u32, u: vec2f) -> vec3f and fn pdf_microfacet_technique(wo: vec3f, m: vec3f, alpha: f32, distribution: u32) -> f32 \
             (or, for anisotropic materials too, fn sample_microfacet_uv_technique(wo: vec3f, alpha_uv: vec2f, distribution: u32, u: vec2f) -> vec3f and fn pdf_microfacet_uv_technique(wo: vec3f, m: vec3f, alpha_uv: vec2f, distribution: u32) -> f32), or both kinds"
        }
        TechniqueKind::Light => {
            "for spherical lights fn sample_light_technique(x: vec3f, n: vec3f, light: SphereLight, u: vec2f) -> vec3f and fn pdf_light_technique(x: vec3f, n: vec3f, light: SphereLight, p: vec3f) -> f32, \
             for triangle lights fn sample_triangle_light_technique(x: vec3f, n: vec3f, light: TriangleLight, u: vec2f) -> vec3f and fn pdf_triangle_light_technique(x: vec3f, n: vec3f, light: TriangleLight, p: vec3f) -> f32, \
             for disk lights fn sample_disk_light_technique(x: vec3f, n: vec3f, light: DiskLight, u: vec2f) -> vec3f and fn pdf_disk_light_technique(x: vec3f, n: vec3f, light: DiskLight, p: vec3f) -> f32, \
             for cylinder lights fn sample_cylinder_light_technique(x: vec3f, n: vec3f, light: CylinderLight, u: vec2f) -> vec3f and fn pdf_cylinder_light_technique(x: vec3f, n: vec3f, light: CylinderLight, p: vec3f) -> f32, or any of them"
        }
        TechniqueKind::Env => "fn sample_env_technique(n: vec3f, u: vec2f) -> vec3f and fn pdf_env_technique(n: vec3f, wi: vec3f) -> f32",
    };
    let report = |message: &str, spans: Vec<(naga::Span, String)>| -> TechniqueError {
        let mut located = spans.iter().filter_map(|(span, label)| Some((locate(span.to_range()?.start)?, label)));
        match located.next() {
            Some(((line, column), label)) if label.is_empty() => TechniqueError::Invalid { message: format!("{file}:{line}:{column}: {message}") },
            Some(((line, column), label)) => TechniqueError::Invalid { message: format!("{file}:{line}:{column}: {message} ({label})") },
            None => TechniqueError::Invalid {
                message: format!("{file}: does not fit the contract of a {} technique, which defines {contract} (shaders/technique.wgsl): {message}", t.kind),
            },
        }
    };
    let neither = match t.kind {
        TechniqueKind::Light => (t.light_shapes() == Default::default()).then_some("no shape's functions"),
        TechniqueKind::Bsdf => (t.bsdf_targets() == Default::default()).then_some("neither the Phong nor the microfacet functions"),
        TechniqueKind::Env => None,
    };
    if t.bsdf_targets().microfacet && t.bsdf_targets().microfacet_uv {
        return Err(TechniqueError::Invalid {
            message: format!("{file}: defines both microfacet pairs, of one alpha and of (alpha_u, alpha_v): define one (the second samples isotropic materials too, alpha_u = alpha_v)"),
        });
    }
    if let Some(neither) = neither {
        return Err(TechniqueError::Invalid {
            message: format!("{file}: does not fit the contract of a {} technique, which defines {contract} (shaders/technique.wgsl): it defines {neither}", t.kind),
        });
    }
    let module = naga::front::wgsl::parse_str(&source)
        .map_err(|e| report(e.message(), e.labels().map(|(s, l)| (s, l.to_string())).collect()))?;
    for (handle, var) in module.global_variables.iter() {
        let span = module.global_variables.get_span(handle);
        if let Some((line, column)) = span.to_range().and_then(|r| locate(r.start)) {
            let name = var.name.clone().unwrap_or_default();
            return Err(TechniqueError::Invalid {
                message: format!("{file}:{line}:{column}: declares the variable `{name}`: a technique is a pure function of its arguments (no var<private>, var<workgroup> or bindings)"),
            });
        }
    }
    for (handle, o) in module.overrides.iter() {
        if let Some((line, column)) = module.overrides.get_span(handle).to_range().and_then(|r| locate(r.start)) {
            let name = o.name.clone().unwrap_or_default();
            return Err(TechniqueError::Invalid { message: format!("{file}:{line}:{column}: declares the override `{name}`: a technique has no pipeline constants") });
        }
    }
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::default())
        .validate(&module)
        .map_err(|e| report(&e.as_inner().to_string(), e.spans().cloned().collect()))?;
    // The guarded file must be as valid (the guard is ours: failing here is pathlab's bug).
    let guarded = assemble_with(&PATH_TRACER, "", crate::accel::BRUTE_FORCE_TRIANGLES, TechniqueFiles::only(t));
    validate(&guarded, &[]).map_err(|e| TechniqueError::Invalid { message: format!("{file}: pathlab's loop guard made it invalid (a bug of pathlab): {e}") })
}

/// The first `n` primes.
pub fn primes(n: usize) -> Vec<u32> {
    let mut primes: Vec<u32> = Vec::with_capacity(n);
    let mut candidate = 2u32;
    while primes.len() < n {
        if primes.iter().take_while(|&&p| p * p <= candidate).all(|&p| candidate % p != 0) {
            primes.push(candidate);
        }
        candidate += 1;
    }
    primes
}

/// Parses and validates `source` with naga, then specialises it with `constants` as the
/// pipelines do (`specialise::specialise`) and validates the result. Returns a readable error.
pub fn validate(source: &str, constants: &[(&str, f64)]) -> Result<(), String> {
    validate_parsed(&specialise::parse(source)?, source, constants)
}

/// `validate` of a module parsed once (`specialise::parse`), for many sets of constants: the
/// module the pipeline's driver is given (`specialise::specialise`) validated.
pub fn validate_parsed(parsed: &specialise::ParsedModule, source: &str, constants: &[(&str, f64)]) -> Result<(), String> {
    let specialised = specialise::specialise(parsed, PATH_TRACER_ENTRY, constants)?;
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::default())
        .validate(&specialised)
        .map_err(|e| format!("specialised module with {constants:?} is invalid: {}", e.emit_to_string(source)))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_primes() {
        assert_eq!(primes(6), vec![2, 3, 5, 7, 11, 13]);
        assert_eq!(primes(HALTON_DIMENSIONS)[255], 1619);
    }

    #[test]
    fn display_pass_is_valid_wgsl() {
        validate(&display_source(), &[]).unwrap();
    }

    #[test]
    fn library_alone_is_valid_wgsl() {
        validate(&assemble(&LIBRARY, ""), &[]).unwrap();
    }
}

#[cfg(test)]
mod path_tracer_tests {
    #[test]
    fn path_tracer_is_valid_wgsl_with_its_defaults() {
        super::validate(&super::path_tracer_source(), &[]).unwrap();
    }

    /// The module of each size class of scene, specialised to a scene of that size.
    #[test]
    fn path_tracer_for_each_triangle_count_is_valid_wgsl() {
        for n in [0u32, 1, 36, crate::accel::BRUTE_FORCE_TRIANGLES, crate::accel::BRUTE_FORCE_TRIANGLES + 1] {
            for limit in [0, crate::accel::BRUTE_FORCE_TRIANGLES] {
                let unrolled = super::unrolled_triangles(n, limit);
                super::validate(&super::path_tracer_source_for(unrolled), &[("NUM_TRIANGLES", n as f64)]).unwrap();
            }
        }
    }
}
