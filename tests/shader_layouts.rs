//! The structs the host shares with the kernels, checked against naga's reflection of the
//! assembled WGSL: size, alignment (the host's size must be a multiple of it, so arrays have the
//! same stride) and the offset of every named field; the `override` constants the host sets
//! are exactly those the module declares; the generated values and bindings are those of the
//! Rust definitions. A field added, moved or re-padded on one side only fails here.

use std::mem::{offset_of, size_of};

use naga::proc::Layouter;

use pathlab::film::AccumPixel;
use pathlab::accel::BvhRecord;
use pathlab::gpu::{pipeline_constants, FrameParams, GpuDeltaLight, GpuLight, GpuMaterial, GpuPlane, GpuQuadric, GpuSphere, GpuTriangle, GpuTriangleNormals, PipelineKey};
use pathlab::gpu::{GpuSphereAxes, GpuTriangleUvs};
use pathlab::method::{BsdfSampling, LightSampling, LightSelect, Preset, Sampler, TriangleSampling};
use pathlab::names::Named;
use pathlab::gpu::SceneFeatures;
use pathlab::shaders::{self, bindings};

fn module(source: &str) -> naga::Module {
    naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)))
}

/// Checks the WGSL struct `name` against the host's `size` and named field offsets.
fn check_struct(module: &naga::Module, name: &str, size: usize, fields: &[(&str, usize)]) {
    let mut layouter = Layouter::default();
    layouter.update(module.to_ctx()).expect("layout");
    let (handle, ty) = module.types.iter().find(|(_, t)| t.name.as_deref() == Some(name)).unwrap_or_else(|| panic!("no struct {name} in the WGSL"));
    let naga::TypeInner::Struct { members, span } = &ty.inner else { panic!("{name} is not a struct") };
    let layout = layouter[handle];
    assert_eq!(*span as usize, size, "{name}: WGSL size {span}, host size {size}");
    assert!(layout.alignment.is_aligned(size as u32), "{name}: host size {size} is not a multiple of the WGSL alignment");
    assert_eq!(layout.to_stride() as usize, size, "{name}: array stride differs");
    let named: Vec<(&str, u32)> =
        members.iter().filter_map(|m| m.name.as_deref().filter(|n| !n.starts_with('_')).map(|n| (n, m.offset))).collect();
    assert_eq!(named.len(), fields.len(), "{name}: WGSL fields {named:?}, host fields {fields:?}");
    for (&(wgsl_name, wgsl_offset), &(host_name, host_offset)) in named.iter().zip(fields) {
        assert_eq!(wgsl_name, host_name, "{name}: field order differs");
        assert_eq!(wgsl_offset as usize, host_offset, "{name}.{host_name}: WGSL offset {wgsl_offset}, host offset {host_offset}");
    }
}

macro_rules! fields {
    ($t:ty: $($f:ident),+) => { &[$((stringify!($f), offset_of!($t, $f))),+] };
}

#[test]
fn shared_structs_match_the_wgsl() {
    let pt = module(&shaders::path_tracer_source());
    check_struct(&pt, "FrameParams", size_of::<FrameParams>(), fields!(FrameParams: camera_origin, width, camera_forward, height,
        camera_right, sample_start, camera_up, sample_count, environment, seed, max_depth, tile_x, tile_y, tile_width, tile_height,
        opaque_zero, accum_row, aperture_radius, focus_distance));
    check_struct(&pt, "AccumPixel", size_of::<AccumPixel>(), fields!(AccumPixel: sum, count, sum_err, rays_lo, sum_sq, rays_hi, sum_sq_err, faults));
    check_struct(&pt, "Sphere", size_of::<GpuSphere>(), fields!(GpuSphere: center, radius, material));
    check_struct(&pt, "Plane", size_of::<GpuPlane>(), fields!(GpuPlane: normal, offset, material));
    // The planes and quadrics' buffer: the planes at their full capacity, then the quadrics.
    let planes = pathlab::scene::MAX_PLANES * size_of::<GpuPlane>();
    check_struct(&pt, "Surfaces", planes + pathlab::scene::MAX_QUADRICS * size_of::<GpuQuadric>(), &[("planes", 0), ("quadrics", planes)]);
    check_struct(&pt, "Quadric", size_of::<GpuQuadric>(), fields!(GpuQuadric: object_x, object_y, object_z, world_x, world_y, world_z, normal, material, area, normal_sign, light, flags));
    check_struct(&pt, "Material", size_of::<GpuMaterial>(), fields!(GpuMaterial: emission, flags, p0, p1, p2, p3, kind, opacity, back, normal_map, bump_map, blend, blend_weight, emission_texture));
    check_struct(&pt, "Triangle", size_of::<GpuTriangle>(), fields!(GpuTriangle: p0, material, p1, light, p2, flags));
    check_struct(&pt, "TriangleNormals", size_of::<GpuTriangleNormals>(), fields!(GpuTriangleNormals: n0, n1, n2));
    check_struct(&pt, "TriangleUvs", size_of::<GpuTriangleUvs>(), fields!(GpuTriangleUvs: uv0, uv1, uv2));
    check_struct(&pt, "SphereAxes", size_of::<GpuSphereAxes>(), fields!(GpuSphereAxes: x, y, z));
    check_struct(
        &pt,
        "BvhRecord",
        size_of::<BvhRecord>(),
        fields!(BvhRecord: lo_left, left, hi_left, first_left, lo_right, first_right, hi_right, counts),
    );
    check_struct(&pt, "LightEntry", size_of::<GpuLight>(), fields!(GpuLight: object, power_prob, alias_index, threshold));
    check_struct(&pt, "DeltaLight", size_of::<GpuDeltaLight>(), fields!(GpuDeltaLight: position, cos_cutoff, direction, cos_beam, intensity, cutoff, x_axis, inv_transition, y_axis, texture, uv_scale));
    let display = module(&shaders::display_source());
    check_struct(&display, "AccumPixel", size_of::<AccumPixel>(), fields!(AccumPixel: sum, count, sum_err, rays_lo, sum_sq, rays_hi, sum_sq_err, faults));
}

/// The value of the module-scope `const NAME: u32`.
fn const_u32(module: &naga::Module, name: &str) -> Option<u32> {
    let (_, c) = module.constants.iter().find(|(_, c)| c.name.as_deref() == Some(name))?;
    match module.global_expressions[c.init] {
        naga::Expression::Literal(naga::Literal::U32(v)) => Some(v),
        ref other => panic!("{name} is {other:?}"),
    }
}

#[test]
fn overrides_set_by_the_host_are_those_the_module_declares() {
    let pt = module(&shaders::path_tracer_source());
    // NUM_LIGHTS is the sum of the kinds' NUM_<KIND>_LIGHTS, computed in the WGSL itself.
    let mut declared: Vec<&str> = pt.overrides.iter().filter_map(|(_, o)| o.name.as_deref()).filter(|&n| n != "NUM_LIGHTS").collect();
    let features = SceneFeatures {
        num_spheres: 2,
        num_planes: 1,
        num_disks: 2,
        num_cylinders: 1,
        num_curve_segments: 2,
        num_bspline_segments: 1,
        num_sdf_grids: 1,
        num_sphere_lights: 1,
        num_triangle_lights: 2,
        num_disk_lights: 1,
        num_cylinder_lights: 1,
        num_environment_lights: 1,
        num_point_lights: 1,
        num_spot_lights: 1,
        num_directional_lights: 1,
        num_projector_lights: 1,
        num_triangles: 4,
        small_vertices: Default::default(),
        has_shading_normals: true,
        has_uvs: true,
        has_masks: true,
        anisotropic_roughness: true,
        has_normal_maps: true,
        has_bump_maps: true,
        textured_opacity: true,
        texture_kinds: 31,
        microfacet_distributions: 3,
        textured_slots: [u16::MAX; pathlab::scene::BsdfKind::ALL.len()],
        has_back_bsdfs: true,
        has_blends: true,
        has_emission_textures: true,
        rr_depth: 3,
        thin_lens: true,
        orthographic: true,
        has_light_textures: true,
        num_occluding_planes: 1,
        has_specular: true,
        bsdf_kinds: u32::MAX,
        transmitting_kinds: u32::MAX,
        has_environment: true,
        has_environment_map: true,
        light_interiors_reachable: true,
        uniform_light_powers: false,
        hide_emitters: true,
        num_media: 1,
        camera_medium: 0,
        max_null_collisions: 64,
    };
    let key = PipelineKey::new(Preset::Best.method(), features, pathlab::method::LightSelect::Power);
    // The method's and scene's, and the adapter's (`PathTracerPipelines::get` sets both).
    let tuning = pathlab::gpu::AdapterTuning::for_device(wgpu::DeviceType::Cpu);
    let mut set: Vec<&str> = pipeline_constants(&key).into_iter().chain(tuning.constants()).map(|(n, _)| n).collect();
    declared.sort_unstable();
    set.sort_unstable();
    assert_eq!(declared, set);
}

#[test]
fn generated_values_and_bindings_are_the_rust_ones() {
    let pt = module(&shaders::path_tracer_source());
    for (prefix, names, values) in [
        ("SAMPLER", Sampler::names(), Sampler::ALL.map(Sampler::constant).to_vec()),
        ("BSDF", BsdfSampling::names(), BsdfSampling::ALL.map(BsdfSampling::constant).to_vec()),
        ("LIGHTS", LightSampling::names(), LightSampling::ALL.map(LightSampling::constant).to_vec()),
        ("LIGHT_SELECT", LightSelect::names(), LightSelect::ALL.map(LightSelect::constant).to_vec()),
        ("TRIANGLES", TriangleSampling::names(), TriangleSampling::ALL.map(TriangleSampling::constant).to_vec()),
    ] {
        for (name, value) in names.iter().zip(values) {
            let wgsl = format!("{prefix}_{}", name.to_uppercase().replace('-', "_"));
            assert_eq!(const_u32(&pt, &wgsl), Some(value), "{wgsl}");
        }
    }
    // Every resource of the path tracer sits at the binding the host binds it to.
    let by_name = |m: &naga::Module, var: &str| {
        m.global_variables.iter().find(|(_, g)| g.name.as_deref() == Some(var)).and_then(|(_, g)| g.binding.as_ref()).map(|b| b.binding)
    };
    for (var, b) in [
        ("frame", bindings::FRAME),
        ("spheres", bindings::SPHERES),
        ("surfaces", bindings::SURFACES),
        ("material_texels", bindings::MATERIALS),
        ("accum", bindings::ACCUM),
        ("halton_primes", bindings::HALTON_PRIMES),
        ("triangles", bindings::TRIANGLES),
        ("triangle_normals", bindings::TRIANGLE_NORMALS),
        ("bvh_nodes", bindings::BVH_NODES),
        ("bvh_parents", bindings::BVH_PARENTS),
        ("light_texels", bindings::LIGHTS),
        ("triangle_uvs", bindings::TRIANGLE_UVS),
        ("sphere_axes", bindings::SPHERE_AXES),
    ] {
        assert_eq!(by_name(&pt, var), Some(b.number), "{var}");
    }
    let display = module(&shaders::display_source());
    for (var, b) in [
        ("display", bindings::DISPLAY_PARAMS),
        ("band", bindings::DISPLAY_BAND),
        ("reference", bindings::DISPLAY_REFERENCE),
        ("colour_map", bindings::DISPLAY_COLOUR_MAP),
        ("shown", bindings::DISPLAY_SHOWN),
    ] {
        assert_eq!(by_name(&display, var), Some(b.number), "{var}");
    }
}

#[test]
fn display_constants_are_the_rust_ones() {
    use pathlab::display::{Transfer, View};
    let display = module(&shaders::display_source());
    for view in View::ALL {
        let wgsl = format!("VIEW_{}", view.name().to_uppercase().replace('-', "_"));
        assert_eq!(const_u32(&display, &wgsl), Some(view.constant()), "{wgsl}");
    }
    assert_eq!(const_u32(&display, "TRANSFER_SRGB"), Some(Transfer::Srgb.code()));
    assert_eq!(const_u32(&display, "TRANSFER_GAMMA"), Some(Transfer::Gamma(2.0).code()));
}

#[test]
fn the_bvh_stack_and_triangle_flags_are_the_rust_ones() {
    let pt = module(&shaders::path_tracer_source());
    assert_eq!(const_u32(&pt, "BVH_MAX_DEPTH"), Some(pathlab::accel::bvh::MAX_DEPTH as u32));
    assert_eq!(const_u32(&pt, "BRUTE_FORCE_TRIANGLES"), Some(pathlab::accel::BRUTE_FORCE_TRIANGLES));
    assert_eq!(const_u32(&pt, "BVH_COUNT_BITS"), Some(pathlab::accel::bvh::COUNT_BITS));
    assert_eq!(const_u32(&pt, "BVH_SELF_LEAF"), Some(pathlab::accel::bvh::SELF_LEAF));
    use pathlab::shaders::flags;
    assert_eq!(const_u32(&pt, "TRIANGLE_TWO_SIDED"), Some(flags::TRIANGLE_TWO_SIDED));
    assert_eq!(const_u32(&pt, "MATERIAL_EMISSIVE"), Some(flags::MATERIAL_EMISSIVE));
    assert_eq!(const_u32(&pt, "MATERIAL_ONE_SIDED"), Some(flags::MATERIAL_ONE_SIDED));
    assert_eq!(const_u32(&pt, "TRIANGLE_HAS_NORMALS"), Some(flags::TRIANGLE_HAS_NORMALS));
}

/// The registry of BSDF kinds: every kind has its number, its file with both entry points (and
/// the delta lobe's probability where it has a delta lobe beside smooth ones), and its
/// override, which the pipeline sets.
#[test]
fn every_bsdf_kind_of_the_registry_is_in_the_kernel() {
    use pathlab::scene::BsdfKind;
    let pt = module(&shaders::path_tracer_source());
    assert_eq!(shaders::files::BSDF_KINDS.len(), BsdfKind::ALL.len());
    for (k, (file, _)) in BsdfKind::ALL.iter().zip(shaders::files::BSDF_KINDS) {
        assert_eq!(const_u32(&pt, &format!("BSDF_KIND_{}", k.stem().to_uppercase())), Some(k.constant()), "{k}");
        assert_eq!(file, format!("bsdfs/{}.wgsl", k.stem()));
        let mut entries = vec![format!("eval_pdf_{}_bsdf", k.stem()), format!("sample_{}_bsdf", k.stem())];
        if k.has_delta_lobe() {
            entries.push(format!("delta_lobe_prob_{}_bsdf", k.stem()));
        }
        for f in entries {
            assert!(pt.functions.iter().any(|(_, g)| g.name.as_deref() == Some(f.as_str())), "{f} missing");
        }
        assert!(pt.overrides.iter().any(|(_, o)| o.name.as_deref() == Some(k.has_override())), "{}", k.has_override());
    }
    // A pipeline sets each kind's override: on for the kinds its scene uses.
    let scene = pathlab::scene::Scene::load(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/veach_mis.xml")).unwrap();
    let features = pathlab::gpu::SceneFeatures::of(&scene);
    let key = PipelineKey::new(Preset::Mis.method(), features, scene.default_light_select());
    let constants = pipeline_constants(&key);
    let on = |name: &str| constants.iter().find(|(n, _)| *n == name).map(|(_, v)| *v);
    assert_eq!((on("HAS_PHONG"), on("HAS_CONDUCTOR"), on("HAS_ROUGH_CONDUCTOR")), (Some(1.0), Some(0.0), Some(1.0)));
}

/// Every kind of the emitter registry has its number, its WGSL file (in the registry's order),
/// its three entry points and its count override; a pipeline counts the environment only where
/// the method samples it.
#[test]
fn every_emitter_kind_of_the_registry_is_in_the_kernel() {
    use pathlab::scene::EmitterKind;
    let pt = module(&shaders::path_tracer_source());
    assert_eq!(shaders::files::EMITTER_KINDS.len(), EmitterKind::ALL.len());
    for (k, (file, _)) in EmitterKind::ALL.iter().zip(shaders::files::EMITTER_KINDS) {
        assert_eq!(const_u32(&pt, &format!("EMITTER_KIND_{}", k.name().to_uppercase())), Some(k.constant()), "{k}");
        assert_eq!(file, format!("emitters/{}.wgsl", k.name()));
        for f in [format!("sample_{}_emitter", k.name()), format!("pdf_{}_emitter", k.name()), format!("eval_{}_emitter", k.name())] {
            assert!(pt.functions.iter().any(|(_, g)| g.name.as_deref() == Some(f.as_str())), "{f} missing");
        }
        assert!(pt.overrides.iter().any(|(_, o)| o.name.as_deref() == Some(k.count_override())), "{}", k.count_override());
    }
    let mut scene = pathlab::scene::Scene::load(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/cornell_box.toml")).unwrap();
    scene.render.environment = glam::DVec3::splat(0.5);
    let features = pathlab::gpu::SceneFeatures::of(&scene);
    let count = |method: pathlab::method::Method, name: &str| {
        let key = PipelineKey::new(method, features, scene.default_light_select());
        pipeline_constants(&key).into_iter().find(|(n, _)| *n == name).map(|(_, v)| v)
    };
    let mis = Preset::Mis.method();
    assert_eq!(count(mis, "NUM_TRIANGLE_LIGHTS"), Some(scene.num_lights() as f64));
    assert_eq!(count(mis, "NUM_ENVIRONMENT_LIGHTS"), Some(0.0));
    assert_eq!(count(pathlab::method::Method { environment: true, ..mis }, "NUM_ENVIRONMENT_LIGHTS"), Some(1.0));
    // Without light sampling nothing samples it.
    assert_eq!(count(pathlab::method::Method { environment: true, ..Preset::Phong.method() }, "NUM_ENVIRONMENT_LIGHTS"), Some(0.0));
}

#[cfg(feature = "viewer")]
#[test]
fn display_params_match_the_wgsl() {
    use pathlab::viewer::display_pass::DisplayParams;
    let display = module(&shaders::display_source());
    check_struct(&display, "DisplayParams", size_of::<DisplayParams>(), fields!(DisplayParams: width, y0, rows, view,
        exposure_scale, transfer, inv_gamma, log_lo, log_hi, row_stride));
}
