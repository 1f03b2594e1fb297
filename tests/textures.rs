//! Textures (src/scene/textures/, shaders/texture.wgsl): Mitsuba's `checkerboard` and `bitmap`
//! as diffuse reflectances, plastics' bases and conductors' reflectances.
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
//! 4. Bitmaps: pathlab's lookup (`Bitmap::eval`) against Mitsuba 3.9.1's own `bitmap` plugin
//!    evaluated at 154 uvs for 13 configurations (every filter and wrap mode, sRGB and raw 8-bit,
//!    grey with alpha, float EXR, sheared and shifted `to_uv`; tests/fixtures/textures/, made by
//!    scripts/bitmap_evals.py): equal to 2e-6. The kernel's lookup against the host's at the same
//!    uvs: equal but for the rounding of the uv arithmetic.
//! 5. The Cornell box with bitmaps on the floor (sRGB PNG, mirrored), back wall (EXR), sphere (raw,
//!    nearest, clamped) and box (grey PNG with alpha) (tests/fixtures/cornell_bitmap/), and with
//!    textures in a plastic's base, a roughplastic's base and a roughconductor's reflectance
//!    (tests/fixtures/cornell_textured_layers/), z-tested against Mitsuba as in 2. A bitmap
//!    lookup without the sRGB decode fails 4 and 5 (55% of channels passing, max |z| 165).
//! 6. Gradients (Mitsuba's `eval_1_grad`, what its bumpmap reads): `Bitmap::eval_1_grad` against
//!    Mitsuba 3.9.1's at the uvs and configurations of 4 (scripts/bitmap_evals.py), and the
//!    kernel's `texture_gradient` against the host's, away from texel centres (where the
//!    gradient jumps): equal to f32 rounding.
//! 7. Checkerboards with `to_uv` that translates, rotates and shears, read from XML as Mitsuba
//!    reads them (the transform's 2D affine part), against Mitsuba 3.9.1's own `checkerboard`
//!    at 64 uvs each (tests/fixtures/textures/checkerboard_evals.json, made by
//!    scripts/checkerboard_evals.py): the same colour but within 1e-5 of a cell edge, where the
//!    rounding of the map decides.

use crate::common;

use common::*;
use glam::DVec3;
use pathlab::method::Preset;
use pathlab::scene::image_file::read_image;
use pathlab::scene::textures::{Bitmap, Filter, Wrap};
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
    test_out[i] = vec4f(texture_slot(vec3f(test_uvs[i].z, 0.0, 0.0), uv_context(test_uvs[i].xy)), 0.0);
}
"#;

/// The kernel's `texture_slot` at each query (u, v, slot, _) over the BSDF data `data`.
fn lookups(queries: &[[f32; 4]], data: &BsdfData) -> Vec<[f32; 4]> {
    let inputs = vec![(0, bytemuck::cast_slice(queries).to_vec()), (shaders::bindings::BSDF_DATA.number, bytemuck::cast_slice(&data.0).to_vec())];
    run_test_kernel(&shaders::LIBRARY, LOOKUP_KERNEL, "lookup_main", inputs, queries.len(), 1)
}

#[test]
fn the_kernels_checkerboard_is_the_hosts() {
    let textures = [
        Texture::Checkerboard { color0: DVec3::new(0.9, 0.5, 0.1), color1: DVec3::new(0.05, 0.2, 0.7), to_uv: [[4.0, 0.0, 0.0], [0.0, 4.0, 0.0]] },
        Texture::Checkerboard { color0: DVec3::splat(0.4), color1: DVec3::splat(0.2), to_uv: [[20.0, 0.0, 0.0], [0.0, 80.0, 0.0]] },
        Texture::Checkerboard { color0: DVec3::ONE, color1: DVec3::ZERO, to_uv: [[-3.0, 0.0, 0.0], [0.0, 0.5, 0.0]] },
        // A turned, sheared and shifted one (Mitsuba's full to_uv).
        Texture::Checkerboard { color0: DVec3::new(0.3, 0.6, 0.9), color1: DVec3::splat(0.05), to_uv: [[3.0, 1.5, -0.25], [-2.0, 4.0, 0.6]] },
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
    let out = lookups(&queries, &data);
    for (q, got) in queries.iter().zip(&out) {
        let expected = textures[q[3] as usize].eval([q[0], q[1]], [0.0; 3]);
        assert_eq!(&got[..3], &expected[..], "texture {} at uv ({}, {})", q[3], q[0], q[1]);
    }
}

/// The bitmaps of tests/fixtures/textures/bitmap_evals.json (scripts/bitmap_evals.py) with
/// their uvs and Mitsuba 3.9.1's values there.
fn mitsuba_bitmap_evals() -> Vec<(Bitmap, Vec<[f32; 2]>, Vec<[f32; 3]>)> {
    mitsuba_bitmap_evals_and_gradients().into_iter().map(|(b, uv, rgb, _)| (b, uv, rgb)).collect()
}

/// `mitsuba_bitmap_evals` with Mitsuba's `eval_1_grad` at each uv (what its bumpmap reads).
fn mitsuba_bitmap_evals_and_gradients() -> Vec<(Bitmap, Vec<[f32; 2]>, Vec<[f32; 3]>, Vec<[f32; 2]>)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/textures");
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("bitmap_evals.json")).unwrap()).unwrap();
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    json["configs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let file = dir.join(c["file"].as_str().unwrap());
            let raw = c["raw"].as_bool().unwrap();
            let m = &c["to_uv"];
            let to_uv = [[f(&m[0][0]), f(&m[0][1]), f(&m[0][2])], [f(&m[1][0]), f(&m[1][1]), f(&m[1][2])]];
            let image = read_image(&file, raw).unwrap();
            let bitmap = Bitmap::new(file, image, Filter::parse(c["filter_type"].as_str().unwrap()).unwrap(), Wrap::parse(c["wrap_mode"].as_str().unwrap()).unwrap(), raw, to_uv);
            let uvs = c["uv"].as_array().unwrap().iter().map(|p| [f(&p[0]) as f32, f(&p[1]) as f32]).collect();
            let rgb = c["rgb"].as_array().unwrap().iter().map(|p| [f(&p[0]) as f32, f(&p[1]) as f32, f(&p[2]) as f32]).collect();
            let grad = c["grad"].as_array().unwrap().iter().map(|p| [f(&p[0]) as f32, f(&p[1]) as f32]).collect();
            (bitmap, uvs, rgb, grad)
        })
        .collect()
}

/// Values equal within float rounding (the sRGB curve: Dr.Jit's is a rational fit, pathlab's
/// table the exact curve; bilinear weights: f32 steps in another order).
fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 2e-6 + 2e-6 * b.abs()
}

#[test]
fn bitmap_lookups_are_mitsubas() {
    // Every filter and wrap mode, sRGB and raw 8-bit, grey with alpha, float EXR, to_uv with
    // shear and translation; uvs over [-2.5, 2.5]^2 and on texel centres and edges.
    let mut checked = 0;
    for (bitmap, uvs, expected) in mitsuba_bitmap_evals() {
        for (uv, e) in uvs.iter().zip(&expected) {
            let got = bitmap.eval(*uv);
            assert!((0..3).all(|c| close(got[c], e[c])), "{} {:?} {:?} raw {} at {uv:?}: pathlab {got:?}, Mitsuba {e:?}", bitmap.file.display(), bitmap.filter, bitmap.wrap, bitmap.raw);
            checked += 1;
        }
    }
    assert!(checked > 2000, "{checked} lookups");
}

#[test]
fn checkerboards_with_any_to_uv_are_mitsubas() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/textures/checkerboard_evals.json");
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    let (mut checked, mut edges) = (0, 0);
    for c in json["configs"].as_array().unwrap() {
        let rgb = |v: &serde_json::Value| format!("{}, {}, {}", f(&v[0]), f(&v[1]), f(&v[2]));
        let bsdf = format!(
            "<bsdf type=\"diffuse\" id=\"b\"><texture type=\"checkerboard\" name=\"reflectance\"><rgb name=\"color0\" value=\"{}\"/><rgb name=\"color1\" value=\"{}\"/><transform name=\"to_uv\">{}</transform></texture></bsdf>",
            rgb(&c["color0"]),
            rgb(&c["color1"]),
            c["to_uv"].as_str().unwrap()
        );
        let scene = load_xml(&xml_with_bsdf(&bsdf, "b"), "c.xml").unwrap();
        let texture = scene.materials.iter().flat_map(|m| m.textures()).next().expect("the checkerboard").clone();
        let Texture::Checkerboard { to_uv: m, .. } = &texture else { panic!("{texture:?}") };
        for (uv, e) in c["uvs"].as_array().unwrap().iter().zip(c["values"].as_array().unwrap()) {
            let uv = [f(&uv[0]) as f32, f(&uv[1]) as f32];
            let got = texture.eval(uv, [0.0; 3]);
            let e = [f(&e[0]) as f32, f(&e[1]) as f32, f(&e[2]) as f32];
            // Within 1e-5 of a cell edge (of the doubled map: cells are half a unit wide), the
            // last bits of the map's rounding pick the side.
            let at_edge = (0..2).any(|r| {
                let x = 2.0 * (m[r][0] * uv[0] as f64 + m[r][1] * uv[1] as f64 + m[r][2]);
                (x - x.round()).abs() < 2e-5
            });
            if at_edge {
                edges += 1;
            } else {
                assert_eq!(got, e, "to_uv {} {m:?} at {uv:?}", c["to_uv"]);
                checked += 1;
            }
        }
    }
    println!("{checked} lookups equal Mitsuba's; {edges} within 1e-5 of a cell edge left out");
    assert!(checked >= 250 && edges <= 6, "{checked} checked, {edges} at edges");
}

/// Whether uv lies within 1e-3 texel of a texel centre along x or y of the bitmap: where the
/// bilinear interpolant's gradient jumps, and the last bit of the position's rounding decides
/// which side's value a lookup gives.
fn near_a_texel_centre(b: &Bitmap, uv: [f32; 2]) -> bool {
    let m = b.to_uv;
    let (u, v) = (uv[0] as f64, uv[1] as f64);
    let px = (m[0][0] * u + m[0][1] * v + m[0][2]) * b.image.width as f64 - 0.5;
    let py = (m[1][0] * u + m[1][1] * v + m[1][2]) * b.image.height as f64 - 0.5;
    (px - px.round()).abs() < 1e-3 || (py - py.round()).abs() < 1e-3
}

#[test]
fn bitmap_gradients_are_mitsubas() {
    // Mitsuba's eval_1_grad (its bumpmap's heights) against `Bitmap::eval_1_grad` at the same
    // uvs and configurations as the lookups, away from texel centres (near_a_texel_centre):
    // equal but for f32 rounding (differences of luminances times the resolution).
    let (mut checked, mut skipped) = (0, 0);
    for (bitmap, uvs, _, expected) in mitsuba_bitmap_evals_and_gradients() {
        for (uv, e) in uvs.iter().zip(&expected) {
            if near_a_texel_centre(&bitmap, *uv) {
                skipped += 1;
                continue;
            }
            let got = bitmap.eval_1_grad(*uv);
            assert!((0..2).all(|c| (got[c] - e[c]).abs() <= 2e-5 * (1.0 + e[c].abs())), "{} {:?} {:?} raw {} to_uv {:?} at {uv:?}: pathlab {got:?}, Mitsuba {e:?}", bitmap.file.display(), bitmap.filter, bitmap.wrap, bitmap.raw, bitmap.to_uv);
            checked += 1;
        }
    }
    println!("{checked} gradients checked, {skipped} near texel centres skipped");
    assert!(checked > 1000, "{checked} gradients");
}

const GRADIENT_KERNEL: &str = r#"
@group(0) @binding(0) var<storage, read> test_uvs: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> test_out: array<vec4f>;

@compute @workgroup_size(64)
fn gradient_main(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x;
    if (i >= arrayLength(&test_uvs)) {
        return;
    }
    test_out[i] = vec4f(texture_gradient(u32(test_uvs[i].z), test_uvs[i].xy), 0.0, 0.0);
}
"#;

#[test]
fn the_kernels_bitmap_gradient_is_the_hosts() {
    let cases = mitsuba_bitmap_evals();
    let mut data = BsdfData::default();
    data.push(&[7.0; 3]);
    let mut queries: Vec<[f32; 4]> = Vec::new();
    for (t, (bitmap, uvs, _)) in cases.iter().enumerate() {
        let start = bitmap.pack(&mut data) as f32;
        queries.extend(uvs.iter().filter(|uv| !near_a_texel_centre(bitmap, **uv)).map(|uv| [uv[0], uv[1], start, t as f32]));
    }
    let inputs = vec![(0, bytemuck::cast_slice(&queries).to_vec()), (shaders::bindings::BSDF_DATA.number, bytemuck::cast_slice(&data.0).to_vec())];
    let out: Vec<[f32; 4]> = run_test_kernel(&shaders::LIBRARY, GRADIENT_KERNEL, "gradient_main", inputs, queries.len(), 1);
    for (q, got) in queries.iter().zip(&out) {
        let b = &cases[q[3] as usize].0;
        let expected = b.eval_1_grad([q[0], q[1]]);
        assert!((0..2).all(|c| (got[c] - expected[c]).abs() <= 2e-5 * (1.0 + expected[c].abs())), "{} {:?} {:?} at ({}, {}): kernel {:?}, host {expected:?}", b.file.display(), b.filter, b.wrap, q[0], q[1], &got[..2]);
    }
}

#[test]
fn the_kernels_bitmap_lookup_is_the_hosts() {
    let cases = mitsuba_bitmap_evals();
    let mut data = BsdfData::default();
    data.push(&[7.0; 3]);
    let mut queries: Vec<[f32; 4]> = Vec::new();
    for (t, (bitmap, uvs, _)) in cases.iter().enumerate() {
        let slot = -(bitmap.pack(&mut data) as f32) - 1.0;
        queries.extend(uvs.iter().map(|uv| [uv[0], uv[1], slot, t as f32]));
    }
    let out = lookups(&queries, &data);
    for (q, got) in queries.iter().zip(&out) {
        let b = &cases[q[3] as usize].0;
        let expected = b.eval([q[0], q[1]]);
        // Equal but for the rounding of the uv arithmetic (fused multiply-adds on lavapipe): a
        // position's last bit (1e-6 at |uv * size| ~ 30) times the steepest texel difference.
        assert!((0..3).all(|c| (got[c] - expected[c]).abs() <= 1e-5 * (1.0 + expected[c].abs())), "{} {:?} {:?} at ({}, {}): kernel {:?}, host {expected:?}", b.file.display(), b.filter, b.wrap, q[0], q[1], &got[..3]);
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
fn mis_and_best_agree_with_mitsuba_on_bitmaps_in_the_cornell_box() {
    let reference = mitsuba_fixture("cornell_bitmap");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/cornell_bitmap/cornell_bitmap.xml"), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let bitmaps = scene.materials.iter().flat_map(|m| m.bsdf.textures()).filter(|t| matches!(t, Texture::Bitmap(_))).count();
    assert_eq!(bitmaps, 4, "floor, back wall, sphere and box textured");
    let methods = [Preset::Mis.method(), Preset::Best.method()];
    agrees_with_reference(&reference, &scene, &methods, |_| (1024, 2), 1500, Preset::Mis.method());
}

#[test]
fn mis_and_best_agree_with_mitsuba_on_textured_plastics_and_metals_in_the_cornell_box() {
    let reference = mitsuba_fixture("cornell_textured_layers");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/cornell_textured_layers/cornell_textured_layers.xml"), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let textured: Vec<&str> = scene.materials.iter().filter(|m| !m.bsdf.textures().is_empty()).map(|m| m.bsdf.kind().toml_name()).collect();
    assert_eq!(textured, ["plastic", "roughconductor", "roughplastic"], "the floor's, box's and sphere's slots textured");
    let methods = [Preset::Mis.method(), Preset::Best.method()];
    agrees_with_reference(&reference, &scene, &methods, |_| (1024, 2), 1500, Preset::Mis.method());
}

#[test]
fn textures_are_read_from_toml_and_xml_and_bad_ones_refused() {
    let with = toml_with_material;
    let s = scene(&with("diffuse = { texture = \"checkerboard\", color0 = [0.8, 0.6, 0.4], to_uv_scale = [20, 80] }"));
    let Bsdf::Phong(p) = &s.materials[0].bsdf else { panic!("not phong") };
    let expected = Texture::Checkerboard { color0: DVec3::new(0.8, 0.6, 0.4), color1: DVec3::splat(0.2), to_uv: [[20.0, 0.0, 0.0], [0.0, 80.0, 0.0]] };
    assert_eq!(p.diffuse_texture.as_ref(), Some(&expected));
    assert_eq!(p.diffuse, expected.mean(), "the mean stands for the texture on the host");
    let cases = [
        ("diffuse = { texture = \"bricks\" }", "unknown texture \"bricks\" (pathlab has checkerboard, bitmap, volume, rawconstant, mesh_attribute)"),
        ("diffuse = { color0 = 0.5 }", "needs `texture = \"checkerboard\"`, `\"bitmap\"` or `\"volume\"`"),
        ("diffuse = { texture = \"checkerboard\", color0 = -1 }", "`color0` of a checkerboard must be a colour >= 0"),
        ("diffuse = { texture = \"checkerboard\", to_uv_scale = [0, 1] }", "two finite non-zero numbers"),
        ("diffuse = { texture = \"checkerboard\", to_uv_scale = [2, 1], to_uv = [[1, 0, 0], [0, 1, 0]] }", "either `to_uv_scale` or `to_uv`"),
        ("diffuse = { texture = \"checkerboard\", to_uv = [[1, 0], [0, 1]] }", "two rows of three finite numbers"),
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
    let expected = Texture::Checkerboard { color0: DVec3::splat(0.4), color1: DVec3::new(0.1, 0.2, 0.3), to_uv: [[10.0, 0.0, 0.0], [0.0, 5.0, 0.0]] };
    assert!(matches!(&s.materials[0].bsdf, Bsdf::Phong(p) if p.diffuse_texture.as_ref() == Some(&expected)), "{:?}", s.materials[0].bsdf);
    for (bsdf, message) in [
        ("<bsdf type=\"diffuse\" id=\"t\"><texture type=\"bricks\" name=\"reflectance\"/></bsdf>", "<texture type=\"bricks\"> is not supported (pathlab has checkerboard, bitmap, volume, rawconstant, mesh_attribute)"),
        ("<bsdf type=\"roughplastic\" id=\"t\"><texture type=\"checkerboard\" name=\"specular_reflectance\"/></bsdf>", "a textured parameter other than diffuse_reflectance is not supported"),
        ("<bsdf type=\"conductor\" id=\"t\"><texture type=\"checkerboard\" name=\"alpha\"/></bsdf>", "a textured parameter other than eta, k, specular_reflectance (and a roughconductor's alpha) is not supported"),
        ("<bsdf type=\"dielectric\" id=\"t\"><texture type=\"checkerboard\" name=\"int_ior\"/></bsdf>", "a textured parameter other than specular_reflectance and specular_transmittance (and a roughdielectric's alpha) is not supported"),
    ] {
        std::fs::write(&path, xml(bsdf)).unwrap();
        let e = Scene::load(&path).unwrap_err().to_string();
        assert!(e.contains("t.xml:3:") && e.contains(message), "{bsdf}: {e}");
    }
}

#[test]
fn bitmaps_are_read_from_toml_and_xml_and_bad_ones_refused() {
    let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/textures");
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(fixtures.join("grid.png"), dir.path().join("grid.png")).unwrap();
    std::fs::write(dir.path().join("picture.tga"), b"not read").unwrap();
    std::fs::write(dir.path().join("broken.png"), b"\x89PNG\r\n\x1a\n and then nothing").unwrap();
    exr::prelude::write_rgb_file(dir.path().join("nan.exr"), 3, 2, |x, y| if (x, y) == (2, 1) { (f32::NAN, 0.0, 0.0) } else { (0.5, 0.5, 0.5) }).unwrap();
    let toml_path = dir.path().join("t.toml");
    let load_toml = |material: &str| {
        std::fs::write(&toml_path, toml_with_material(material)).unwrap();
        Scene::load(&toml_path)
    };
    // A bitmap relative to the scene's folder, with every parameter.
    let s = load_toml("diffuse = { texture = \"bitmap\", filename = \"grid.png\", filter_type = \"nearest\", wrap_mode = \"mirror\", to_uv = [[2, 0, 0.5], [0, 3, 0]] }").unwrap();
    let Bsdf::Phong(p) = &s.materials[0].bsdf else { panic!("not phong") };
    let Some(Texture::Bitmap(b)) = &p.diffuse_texture else { panic!("{:?}", p.diffuse_texture) };
    assert_eq!((b.image.width, b.image.height, b.filter, b.wrap, b.raw, b.to_uv), (5, 3, Filter::Nearest, Wrap::Mirror, false, [[2.0, 0.0, 0.5], [0.0, 3.0, 0.0]]));
    assert_eq!(p.diffuse, DVec3::from(b.image.mean()), "the image's mean stands for it on the host");
    // A texture changes the scene's identity; so does its image's content.
    let hash = s.content_hash();
    let s2 = load_toml("diffuse = { texture = \"bitmap\", filename = \"grid.png\", filter_type = \"nearest\", wrap_mode = \"mirror\", to_uv = [[2, 0, 0.5], [0, 3, 0]], raw = true }").unwrap();
    assert_ne!(hash, s2.content_hash());

    let cases = [
        ("diffuse = { texture = \"bitmap\" }", "a bitmap needs `filename"),
        ("diffuse = { texture = \"bitmap\", filename = \"wood.png\" }", "image file \"wood.png\" not found (searched"),
        ("diffuse = { texture = \"bitmap\", filename = \"picture.tga\" }", "unsupported image format \".tga\""),
        ("diffuse = { texture = \"bitmap\", filename = \"broken.png\" }", "cannot decode it"),
        ("diffuse = { texture = \"bitmap\", filename = \"nan.exr\" }", "pixel (2, 1) (from the top left) is not finite"),
        ("diffuse = { texture = \"bitmap\", filename = \"grid.png\", wrap_mode = \"tile\" }", "`wrap_mode` of a bitmap must be one of repeat, mirror, clamp"),
        ("diffuse = { texture = \"bitmap\", filename = \"grid.png\", to_uv = [1, 2] }", "two rows of three finite numbers"),
        ("diffuse = { texture = \"bitmap\", filename = \"grid.png\", gamma = 2.2 }", "unknown key `gamma` of a bitmap"),
    ];
    for (material, message) in cases {
        match load_toml(material) {
            Err(SceneError::Invalid(d)) => assert!(d[0].field == "materials.m.diffuse" && d[0].message.contains(message) && d[0].line >= 1, "{material}: {}", d[0]),
            other => panic!("{material}: accepted ({:?})", other.map(|s| s.materials[0].clone())),
        }
    }

    // XML: the file found by Mitsuba's resolver; `to_uv` the 4x4's 2D affine part.
    let xml_path = dir.path().join("t.xml");
    let bitmap = |inner: &str| xml_with_bsdf(&format!("<bsdf type=\"diffuse\" id=\"t\"><texture type=\"bitmap\" name=\"reflectance\">{inner}</texture></bsdf>"), "t");
    std::fs::write(&xml_path, bitmap("<string name=\"filename\" value=\"grid.png\"/><string name=\"wrap_mode\" value=\"clamp\"/><boolean name=\"raw\" value=\"true\"/><transform name=\"to_uv\"><scale x=\"4\" y=\"2\"/></transform><boolean name=\"accel\" value=\"false\"/><string name=\"format\" value=\"uint8\"/>")).unwrap();
    let s = Scene::load(&xml_path).unwrap();
    // Mitsuba's storage choices, as it writes them (`accel` a boolean, `format` a string): warned.
    assert_eq!(s.warnings.iter().filter(|w| w.message.contains("is a storage choice")).count(), 2, "{:?}", s.warnings);
    let Bsdf::Phong(p) = &s.materials[0].bsdf else { panic!("not phong") };
    let Some(Texture::Bitmap(b)) = &p.diffuse_texture else { panic!("{:?}", p.diffuse_texture) };
    assert_eq!((b.file.clone(), b.wrap, b.raw, b.to_uv), (dir.path().join("grid.png"), Wrap::Clamp, true, [[4.0, 0.0, 0.0], [0.0, 2.0, 0.0]]));
    // The 2D affine part, translation included, as Mitsuba 3.9.1 keeps it (its own `to_uv`,
    // read back with mi.traverse after loading these transforms: [[2, 0, -0.5], [0, 2, -0.5]]
    // and [[1, 2, 7], [3, 4, 8]]; mitsuba-data's texture_interp test scene shifts its tiles so).
    for (transform, expected) in [
        ("<scale value=\"2\"/><translate value=\"-.5,-.5, 0\"/>", [[2.0, 0.0, -0.5], [0.0, 2.0, -0.5]]),
        ("<matrix value=\"1 2 5 7  3 4 6 8  9 9 9 9  0 0 0 1\"/>", [[1.0, 2.0, 7.0], [3.0, 4.0, 8.0]]),
    ] {
        std::fs::write(&xml_path, bitmap(&format!("<string name=\"filename\" value=\"grid.png\"/><transform name=\"to_uv\">{transform}</transform>"))).unwrap();
        let s = Scene::load(&xml_path).unwrap();
        let Bsdf::Phong(p) = &s.materials[0].bsdf else { panic!("not phong") };
        let Some(Texture::Bitmap(b)) = &p.diffuse_texture else { panic!("{:?}", p.diffuse_texture) };
        assert_eq!(b.to_uv, expected, "{transform}");
    }
    // A checkerboard's `to_uv` keeps its translation too (as Mitsuba's: until 2026-12-05
    // pathlab refused it), and `convert` writes it as the TOML `to_uv`.
    std::fs::write(&xml_path, xml_with_bsdf("<bsdf type=\"diffuse\" id=\"t\"><texture type=\"checkerboard\" name=\"reflectance\"><transform name=\"to_uv\"><translate x=\"0.5\"/></transform></texture></bsdf>", "t")).unwrap();
    let s = Scene::load(&xml_path).unwrap();
    let Bsdf::Phong(p) = &s.materials[0].bsdf else { panic!("not phong") };
    assert!(matches!(&p.diffuse_texture, Some(Texture::Checkerboard { to_uv, .. }) if *to_uv == [[1.0, 0.0, 0.5], [0.0, 1.0, 0.0]]), "{:?}", p.diffuse_texture);
    let (toml, _) = pathlab::scene::mitsuba::to_toml(&xml_path, &[], dir.path()).unwrap();
    assert!(toml.contains("to_uv = [[1.0, 0.0, 0.5], [0.0, 1.0, 0.0]]"), "{toml}");
    let toml_path = dir.path().join("t.toml");
    std::fs::write(&toml_path, &toml).unwrap();
    assert_eq!(Scene::load(&toml_path).unwrap().content_hash(), s.content_hash());
    // A texture defined at the top level and taken by `<ref name id>`, before or after it.
    let wood = "<texture type=\"bitmap\" id=\"wood\"><string name=\"filename\" value=\"grid.png\"/><string name=\"filter_type\" value=\"nearest\"/></texture>";
    let user = "<bsdf type=\"roughplastic\" id=\"t\"><ref name=\"diffuse_reflectance\" id=\"wood\"/></bsdf>";
    for defs in [format!("{wood}{user}"), format!("{user}{wood}")] {
        std::fs::write(&xml_path, xml_with_bsdf(&defs, "t")).unwrap();
        let s = Scene::load(&xml_path).unwrap_or_else(|e| panic!("{defs}: {e}"));
        let Bsdf::RoughPlastic(p) = &s.materials[0].bsdf else { panic!("not a rough plastic: {:?}", s.materials[0].bsdf) };
        assert!(matches!(&p.layers.diffuse_texture, Some(Texture::Bitmap(b)) if b.filter == Filter::Nearest), "{defs}: {:?}", p.layers.diffuse_texture);
    }
    for (inner, message) in [
        ("<string name=\"filename\" value=\"wood.png\"/>", "image file \"wood.png\" not found (searched"),
        ("", "<texture type=\"bitmap\"> needs <string name=\"filename\">"),
        ("<string name=\"filename\" value=\"grid.png\"/><string name=\"filter_type\" value=\"cubic\"/>", "`filter_type` of a bitmap must be one of bilinear, nearest"),
    ] {
        std::fs::write(&xml_path, bitmap(inner)).unwrap();
        let e = Scene::load(&xml_path).unwrap_err().to_string();
        assert!(e.contains("t.xml:3:") && e.contains(message), "{inner}: {e}");
    }
}

/// A mesh's texture coordinates enter the scene's hash where a texture reads them: a textured
/// quad and the same quad with `flip_tex_coords = false` render different images and must not
/// hash alike (a checkpoint or shard of one would be taken for the other); untextured, the uvs
/// change nothing and the hash stays as before.
#[test]
fn mesh_texture_coordinates_enter_the_hash_where_a_texture_reads_them() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("quad.ply"),
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float u\nproperty float v\n\
         element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0 0.1\n1 0 0 1 0.1\n1 1 0 1 0.7\n0 1 0 0 0.7\n4 0 1 2 3\n",
    )
    .unwrap();
    let scene = |diffuse: &str, flip: bool| {
        let text = format!(
            "[camera]\nposition = [0.5, 0.5, 2]\nlook_at = [0.5, 0.5, 0]\nup = [0, 1, 0]\nfov_x = 50\n[render]\nwidth = 8\nheight = 8\nmax_depth = 2\n\
             [materials.m]\ndiffuse = {diffuse}\n[[meshes]]\nfile = \"quad.ply\"\nmaterial = \"m\"\nflip_tex_coords = {flip}\n"
        );
        Scene::parse(&text, dir.path().join("s.toml")).unwrap()
    };
    let checker = "{ texture = \"checkerboard\", to_uv_scale = [2, 2] }";
    assert_ne!(scene(checker, true).content_hash(), scene(checker, false).content_hash(), "textured: uvs are hashed");
    assert_eq!(scene("0.5", true).content_hash(), scene("0.5", false).content_hash(), "untextured: uvs change nothing");
}
