//! Textures (src/scene/textures.rs, shaders/texture.wgsl): Mitsuba's `checkerboard` as a
//! diffuse reflectance.
//!
//! 1. The kernel's lookup (`texture_slot`, the reference to a record in the BSDF data as the host
//!    packs it) against the host's twin (`Texture::eval`, f32) at 4096 uvs spread over [-3, 3]^2
//!    and at the cells' corners: equal colours, exactly.
//! 2. The Cornell box with a checkerboard floor (the rectangle's uvs), sphere (its longitude and
//!    latitude) and tall box (each face's square) (tests/fixtures/cornell_checkerboard/) against
//!    Mitsuba 3.9.1 loading the same file (64x64, 65536 spp in 64 passes with the per-pixel
//!    variance of its mean; scripts/cornell_checkerboard_reference.sh), z-tested on blocks as
//!    tests/cornell_box.rs does (at least 99.75% of channels passing; `mis` scaled by 1.05 is
//!    rejected), for `mis` and `best`. Fails falsely with probability below 0.01.
//! 3. TOML and XML textures are read, bad ones refused naming the field or line and column.

use crate::common;

use common::*;
use glam::{DVec2, DVec3};
use pathlab::gpu::KernelRun;
use pathlab::method::Preset;
use pathlab::scene::{Bsdf, BsdfData, Scene, SceneError, Texture};
use pathlab::shaders;

const LOOKUP_KERNEL: &str = r#"
@group(0) @binding(0) var<storage, read> test_uvs: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> test_out: array<vec4f>;

@compute @workgroup_size(64)
fn lookup_main(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x;
    if (i >= arrayLength(&test_uvs)) {
        return;
    }
    // The slot as a material packs it: x = -(start + 1).
    test_out[i] = vec4f(texture_slot(vec3f(test_uvs[i].z, 0.0, 0.0), test_uvs[i].xy), 0.0);
}
"#;

#[test]
fn the_kernels_checkerboard_is_the_hosts() {
    let textures = [
        Texture::Checkerboard { color0: DVec3::new(0.9, 0.5, 0.1), color1: DVec3::new(0.05, 0.2, 0.7), to_uv_scale: DVec2::new(4.0, 4.0) },
        Texture::Checkerboard { color0: DVec3::splat(0.4), color1: DVec3::splat(0.2), to_uv_scale: DVec2::new(20.0, 80.0) },
        Texture::Checkerboard { color0: DVec3::ONE, color1: DVec3::ZERO, to_uv_scale: DVec2::new(-3.0, 0.5) },
    ];
    let mut data = BsdfData::default();
    // Something before the textures, as other materials' data would be.
    data.push(&[7.0; 5]);
    let starts: Vec<u32> = textures.iter().map(|t| t.pack(&mut data)).collect();
    let mut queries: Vec<[f32; 4]> = Vec::new();
    let mut state = 0x2545_f491_u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for (t, &start) in starts.iter().enumerate() {
        let slot = -(start as f32) - 1.0;
        for _ in 0..4096 {
            queries.push([(next() * 6.0 - 3.0) as f32, (next() * 6.0 - 3.0) as f32, slot, t as f32]);
        }
        for corner in [0.0f32, 0.125, 0.25, 0.5, 1.0, -0.25, -0.5] {
            queries.push([corner, corner, slot, t as f32]);
            queries.push([corner, 0.3, slot, t as f32]);
        }
    }
    let source = shaders::assemble(&shaders::LIBRARY, LOOKUP_KERNEL);
    let run = KernelRun {
        source: &source,
        entry: "lookup_main",
        constants: &[],
        inputs: vec![(0, bytemuck::cast_slice(&queries).to_vec()), (shaders::bindings::BSDF_DATA.number, bytemuck::cast_slice(&data.0).to_vec())],
        uniforms: vec![],
        output: (1, (queries.len() * 16) as u64),
        workgroups: (queries.len() as u32).div_ceil(64),
    };
    let out: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&run.run(gpu()).expect("texture lookup kernel"));
    for (q, got) in queries.iter().zip(&out) {
        let expected = textures[q[3] as usize].eval([q[0], q[1]]);
        assert_eq!(&got[..3], &expected[..], "texture {} at uv ({}, {})", q[3], q[0], q[1]);
    }
}

#[test]
fn mis_and_best_agree_with_mitsuba_on_checkerboards_in_the_cornell_box() {
    let reference = mitsuba_fixture("cornell_checkerboard");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene =
        Scene::load_with(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/cornell_checkerboard/cornell_checkerboard.xml"), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let textured = scene.materials.iter().filter(|m| matches!(&m.bsdf, Bsdf::Phong(p) if p.diffuse_texture.is_some())).count();
    assert_eq!(textured, 3, "floor, sphere and box textured");
    let methods = [Preset::Mis.method(), Preset::Best.method()];
    agrees_with_reference(&reference, &scene, &methods, |_| (1024, 2), 1500, Preset::Mis.method());
}

#[test]
fn textures_are_read_from_toml_and_xml_and_bad_ones_refused() {
    let with = toml_with_material;
    let s = scene(&with("diffuse = { texture = \"checkerboard\", color0 = [0.8, 0.6, 0.4], to_uv_scale = [20, 80] }"));
    let Bsdf::Phong(p) = &s.materials[0].bsdf else { panic!("not phong") };
    let expected = Texture::Checkerboard { color0: DVec3::new(0.8, 0.6, 0.4), color1: DVec3::splat(0.2), to_uv_scale: DVec2::new(20.0, 80.0) };
    assert_eq!(p.diffuse_texture.as_ref(), Some(&expected));
    assert_eq!(p.diffuse, expected.mean(), "the mean stands for the texture on the host");
    let cases = [
        ("diffuse = { texture = \"bitmap\" }", "unknown texture \"bitmap\" (pathlab has checkerboard)"),
        ("diffuse = { color0 = 0.5 }", "needs `texture = \"checkerboard\"`"),
        ("diffuse = { texture = \"checkerboard\", color0 = -1 }", "`color0` of a checkerboard must be a colour >= 0"),
        ("diffuse = { texture = \"checkerboard\", to_uv_scale = [0, 1] }", "two finite non-zero numbers"),
        ("diffuse = { texture = \"checkerboard\", colour0 = 1 }", "unknown key `colour0`"),
    ];
    for (material, message) in cases {
        match Scene::parse(&with(material), "t.toml") {
            Err(SceneError::Invalid(d)) => assert!(d[0].field == "materials.m.diffuse" && d[0].message.contains(message) && d[0].line >= 1, "{material}: {}", d[0]),
            other => panic!("{material}: accepted ({:?})", other.map(|s| s.materials[0].clone())),
        }
    }

    let xml = |bsdf: &str| xml_with_bsdf(bsdf, "t");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.xml");
    std::fs::write(&path, xml("<bsdf type=\"diffuse\" id=\"t\"><texture type=\"checkerboard\" name=\"reflectance\"><rgb name=\"color1\" value=\"0.1, 0.2, 0.3\"/><transform name=\"to_uv\"><scale x=\"10\" y=\"5\"/></transform></texture></bsdf>")).unwrap();
    let s = Scene::load(&path).unwrap();
    let expected = Texture::Checkerboard { color0: DVec3::splat(0.4), color1: DVec3::new(0.1, 0.2, 0.3), to_uv_scale: DVec2::new(10.0, 5.0) };
    assert!(matches!(&s.materials[0].bsdf, Bsdf::Phong(p) if p.diffuse_texture.as_ref() == Some(&expected)), "{:?}", s.materials[0].bsdf);
    for (bsdf, message) in [
        ("<bsdf type=\"diffuse\" id=\"t\"><texture type=\"bitmap\" name=\"reflectance\"><string name=\"filename\" value=\"a.png\"/></texture></bsdf>", "<texture type=\"bitmap\"> is not supported (pathlab has checkerboard)"),
        ("<bsdf type=\"diffuse\" id=\"t\"><texture type=\"checkerboard\" name=\"reflectance\"><transform name=\"to_uv\"><rotate z=\"1\" angle=\"30\"/></transform></texture></bsdf>", "only <scale> is supported"),
        ("<bsdf type=\"roughplastic\" id=\"t\"><texture type=\"checkerboard\" name=\"diffuse_reflectance\"/></bsdf>", "a textured parameter is not supported"),
    ] {
        std::fs::write(&path, xml(bsdf)).unwrap();
        let e = Scene::load(&path).unwrap_err().to_string();
        assert!(e.contains("t.xml:3:") && e.contains(message), "{bsdf}: {e}");
    }
}
