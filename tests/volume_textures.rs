//! Mitsuba's `volume` texture around a `gridvolume` (`Texture::Volume`,
//! src/scene/textures/volume.rs; `eval_volume_texture` in shaders/texture.wgsl): a grid of
//! colours looked up at the hit's world position.
//!
//! - The host's lookup against Mitsuba 3.9.1's own `eval` and `eval_1` at 234 points for seven
//!   configurations (trilinear and nearest; clamp, repeat and mirror; placed, turned and
//!   `use_grid_bbox`; one and three channels; tests/fixtures/volume/volume_evals.json, made by
//!   scripts/volume_evals.py), and the kernel's lookup against the host's, bit for bit.
//! - tests/fixtures/volume/volume.xml (a diffuse sphere coloured by an RGB grid, a cube greyed by
//!   a repeated single-channel grid, a rough gold sphere whose alpha is a grid's luminance)
//!   rendered by `mis` and `best`, z-tested against Mitsuba 3.9.1 rendering the same file (48x48,
//!   65536 spp in 64 passes with the per-pixel variance of its mean;
//!   scripts/xml_fixture_reference.sh tests/fixtures/volume/volume.xml), on 2x2 blocks as
//!   tests/cornell_box.rs does (at least 99.75% of channels passing, Šidák-corrected: fails
//!   falsely with probability below 0.01; `mis` scaled by 1.05 is rejected).
//! - Bad grids and volume elements refused, naming the file and what is wrong.

use crate::common;

use common::*;
use pathlab::method::{Method, Preset};
use pathlab::scene::textures::{GridVolume, Wrap};
use pathlab::scene::{BsdfData, Scene, Texture};
use pathlab::shaders;

fn dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/volume")
}

/// The configurations of volume_evals.json as pathlab's textures (read through the TOML form),
/// with the points and Mitsuba's values there.
fn mitsuba_evals() -> Vec<(Texture, Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<f32>)> {
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir().join("volume_evals.json")).unwrap()).unwrap();
    let floats = |v: &serde_json::Value| v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap() as f32).collect::<Vec<f32>>();
    let triples = |v: &serde_json::Value| floats(v).chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect::<Vec<[f32; 3]>>();
    json["configs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let rows: Vec<String> = c["to_world"].as_array().unwrap().iter().map(|r| format!("[{}]", r.as_array().unwrap().iter().map(|x| format!("{:?}", x.as_f64().unwrap())).collect::<Vec<_>>().join(", "))).collect();
            let text = format!(
                "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 40\n[render]\nwidth = 4\nheight = 4\nmax_depth = 2\n\
                 [materials.m]\ndiffuse = {{ texture = \"volume\", filename = \"{}\", filter_type = \"{}\", wrap_mode = \"{}\", use_grid_bbox = {}, to_world = [{}] }}\n\
                 [materials.lamp]\nemission = 1\n[[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n[[spheres]]\ncenter = [0, 3, 0]\nradius = 0.5\nmaterial = \"lamp\"\n",
                dir().join(c["file"].as_str().unwrap()).display(),
                c["filter_type"].as_str().unwrap(),
                c["wrap_mode"].as_str().unwrap(),
                c["use_grid_bbox"].as_bool().unwrap(),
                rows.join(", ")
            );
            let scene = Scene::parse(&text, dir().join("evals.toml")).unwrap_or_else(|e| panic!("{e}\n{text}"));
            let t = scene.materials.iter().find_map(|m| m.bsdf.textures().first().map(|t| (*t).clone())).expect("a textured material");
            (t, triples(&c["points"]), triples(&c["rgb"]), floats(&c["eval_1"]))
        })
        .collect()
}

#[test]
fn grid_lookups_are_mitsubas() {
    let evals = mitsuba_evals();
    assert_eq!(evals.len(), 7);
    let mut skipped = 0;
    for (k, (t, points, rgb, one)) in evals.iter().enumerate() {
        for ((p, expected), e1) in points.iter().zip(rgb).zip(one) {
            // A nearest lookup on a cell's face picks either cell by the last bit of the map's
            // arithmetic (Mitsuba's fused multiply-adds in f32, ours not): such points, which
            // the list has on purpose, are skipped there.
            if on_a_face(t, *p) {
                skipped += 1;
                continue;
            }
            let got = t.eval([0.0; 2], *p);
            for c in 0..3 {
                assert!((got[c] - expected[c]).abs() <= 2e-6 * expected[c].abs().max(1.0), "configuration {k} at {p:?}: {got:?}, Mitsuba {expected:?}");
            }
            let g1 = t.eval_1([0.0; 2], *p);
            assert!((g1 - e1).abs() <= 2e-6, "configuration {k} at {p:?}: eval_1 {g1}, Mitsuba {e1}");
        }
    }
    assert!(skipped <= 100, "{skipped} of {} lookups skipped", evals.len() * 234);
}

/// Whether `p` lies within rounding of a cell face of a nearest-filtered grid.
fn on_a_face(t: &Texture, p: [f32; 3]) -> bool {
    let Texture::Volume(v) = t else { return false };
    if v.trilinear {
        return false;
    }
    (0..3).any(|r| {
        let m = v.to_local[r];
        let x = (m[0] * p[0] as f64 + m[1] * p[1] as f64 + m[2] * p[2] as f64 + m[3]) * v.res[r] as f64;
        (x - x.round()).abs() < 1e-4
    })
}

const LOOKUP_KERNEL: &str = r#"
@group(0) @binding(0) var<storage, read> test_points: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> test_out: array<vec4f>;

@compute @workgroup_size(64)
fn lookup_main(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x;
    if (i >= arrayLength(&test_points)) {
        return;
    }
    // The slot as a material packs it: x = -(start + 1); the point in xyz of the query.
    let q = test_points[i];
    let slot = q.w;
    test_out[i] = vec4f(texture_slot(vec3f(slot, 0.0, 0.0), TextureEvalContext(vec2f(0.0), q.xyz, INVALID, vec2f(0.0))), scalar_texture_slot(slot, TextureEvalContext(vec2f(0.0), q.xyz, INVALID, vec2f(0.0))));
}
"#;

#[test]
fn the_kernels_grid_lookup_is_the_hosts() {
    let evals = mitsuba_evals();
    let mut data = BsdfData::default();
    data.push(&[7.0; 5]);
    let starts: Vec<u32> = evals.iter().map(|(t, ..)| t.pack(&mut data)).collect();
    let mut queries: Vec<[f32; 4]> = Vec::new();
    let mut which = Vec::new();
    for (k, (_, points, ..)) in evals.iter().enumerate() {
        for p in points {
            queries.push([p[0], p[1], p[2], -(starts[k] as f32) - 1.0]);
            which.push(k);
        }
    }
    let inputs = vec![(0, bytemuck::cast_slice(&queries).to_vec()), (shaders::bindings::BSDF_DATA.number, bytemuck::cast_slice(&data.0).to_vec())];
    let out = run_test_kernel(&shaders::LIBRARY, LOOKUP_KERNEL, "lookup_main", inputs, queries.len(), 1);
    let cpu_arithmetic = gpu().info.device_type == wgpu::DeviceType::Cpu;
    for ((q, got), &k) in queries.iter().zip(&out).zip(&which) {
        let t = &evals[k].0;
        let p = [q[0], q[1], q[2]];
        let expected = t.eval([0.0; 2], p);
        let e1 = t.eval_1([0.0; 2], p);
        if cpu_arithmetic {
            // lavapipe: the host twin's arithmetic, bit for bit.
            assert_eq!(&got[..3], &expected[..], "configuration {k} at {p:?}");
            assert_eq!(got[3], e1, "configuration {k} at {p:?}: eval_1");
        } else {
            // A GPU may fuse multiply-adds in the map and the interpolation.
            for c in 0..3 {
                assert!((got[c] - expected[c]).abs() <= 1e-5, "configuration {k} at {p:?}: {got:?} against {expected:?}");
            }
        }
    }
}

#[test]
fn volume_textures_agree_with_mitsuba() {
    let reference = mitsuba_fixture("volume");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(dir().join("volume.xml"), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let volumes = scene.materials.iter().flat_map(|m| m.bsdf.textures()).filter(|t| matches!(t, Texture::Volume(_))).count();
    assert_eq!(volumes, 3, "three volume textures");
    let methods: Vec<Method> = ["mis", "best"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (1024, 2), 2500, Preset::Mis.method());
}

#[test]
fn bad_grids_and_volume_elements_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let good = std::fs::read(dir().join("rgb.vol")).unwrap();
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("magic.vol", [b"VOX".as_slice(), &good[3..]].concat(), "not a Mitsuba .vol grid"),
        ("version.vol", [b"VOL\x02".as_slice(), &good[4..]].concat(), "version 2"),
        ("encoding.vol", [&good[..4], &2i32.to_le_bytes()[..], &good[8..]].concat(), "encoding 2"),
        ("channels.vol", [&good[..20], &6i32.to_le_bytes()[..], &good[24..]].concat(), "6 channels"),
        ("short.vol", good[..good.len() - 4].to_vec(), "bytes where its header"),
        ("negative.vol", [&good[..48], &(-1.0f32).to_le_bytes()[..], &good[52..]].concat(), "cell (0, 0, 0) holds -1"),
        ("empty.vol", [&good[..8], &0i32.to_le_bytes()[..], &good[12..]].concat(), "cell counts 0 x 3 x 2"),
    ];
    for (name, bytes, message) in cases {
        std::fs::write(tmp.path().join(name), bytes).unwrap();
        let xml = xml_with_bsdf(&format!("<bsdf type=\"diffuse\" id=\"v\"><texture name=\"reflectance\" type=\"volume\"><volume name=\"volume\" type=\"gridvolume\"><string name=\"filename\" value=\"{name}\"/></volume></texture></bsdf>"), "v");
        let path = tmp.path().join(format!("{name}.xml"));
        std::fs::write(&path, xml).unwrap();
        let err = Scene::load(&path).unwrap_err().to_string();
        assert!(err.contains(name) && err.contains(message), "{name}: {err}");
    }
    // Elements pathlab does not read: another volume plugin, a constant volume, a missing file,
    // an unknown filter.
    std::fs::copy(dir().join("rgb.vol"), tmp.path().join("rgb.vol")).unwrap();
    for (inner, message) in [
        ("<volume name=\"volume\" type=\"constvolume\"/>", "<volume type=\"constvolume\"> is not supported"),
        ("<rgb name=\"volume\" value=\"0.5\"/>", "a constant volume"),
        ("<volume name=\"volume\" type=\"gridvolume\"><string name=\"filename\" value=\"nowhere.vol\"/></volume>", "nowhere.vol"),
        ("<volume name=\"volume\" type=\"gridvolume\"><string name=\"filename\" value=\"rgb.vol\"/><string name=\"filter_type\" value=\"cubic\"/></volume>", "filter_type"),
    ] {
        let xml = xml_with_bsdf(&format!("<bsdf type=\"diffuse\" id=\"v\"><texture name=\"reflectance\" type=\"volume\">{inner}</texture></bsdf>"), "v");
        let path = tmp.path().join("refused.xml");
        std::fs::write(&path, xml).unwrap();
        let err = Scene::load(&path).unwrap_err().to_string();
        assert!(err.contains("refused.xml:3:") && err.contains(message), "{inner}: {err}");
    }
    // The TOML form's keys.
    for (table, message) in [
        ("{ texture = \"volume\", filename = \"rgb.vol\", colour = 1 }", "unknown key `colour` of a volume"),
        ("{ texture = \"volume\", filename = \"rgb.vol\", wrap_mode = \"tile\" }", "`wrap_mode` of a volume must be one of repeat, mirror, clamp"),
        ("{ texture = \"volume\", filename = \"rgb.vol\", to_world = [[0, 0, 0, 1], [0, 0, 0, 1], [0, 0, 0, 1]] }", "an invertible affine map"),
        ("{ texture = \"volume\" }", "a volume needs `filename"),
    ] {
        let err = Scene::parse(&toml_with_material(&format!("diffuse = {table}")), dir().join("t.toml")).unwrap_err().to_string();
        assert!(err.contains("materials.m.diffuse") && err.contains(message), "{table}: {err}");
    }
    // A grid is a GridVolume whatever its placement: the same file read twice is equal.
    let a = GridVolume::new("a.vol".into(), [1, 1, 1], 1, vec![0.5], true, Wrap::Clamp, false, [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]]);
    assert_eq!(a.eval([3.0, -2.0, 0.1]), [0.5; 3]);
}
