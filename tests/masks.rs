//! Mitsuba's `mask` (`Material::opacity`, shaders/bsdfs/mask.wgsl): rays pass straight through a
//! masked surface with probability 1 - opacity and scatter off its BSDF otherwise; shadow rays
//! do not see through it. tests/fixtures/mask/mask.xml (a checkerboard-masked panel casting a
//! chequered shadow, a masked two-sided plastic sphere, a bitmap-masked one-sided panel seen from
//! behind) rendered by `mis`, `best` and `nee` is z-tested against Mitsuba 3.9.1 rendering the
//! same file (48x48, 65536 spp in 64 passes with the per-pixel variance of its mean;
//! scripts/xml_fixture_reference.sh tests/fixtures/mask/mask.xml), on 2x2 blocks as
//! tests/cornell_box.rs does (at least 99.75% of channels passing, Šidák-corrected: fails
//! falsely with probability below 0.01; `mis` scaled by 1.05 is rejected). The sampling of a
//! masked BSDF is chi-square tested with the other routines (tests/chi2_sampling.rs,
//! `mask_routines`).

use crate::common;

use common::*;
use pathlab::method::{Method, Preset};
use pathlab::scene::{Opacity, Scene};

fn fixture() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/mask/mask.xml")
}

#[test]
fn masked_surfaces_agree_with_mitsuba() {
    let reference = mitsuba_fixture("mask");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(fixture(), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let masked: Vec<&Opacity> = scene.materials.iter().filter_map(|m| m.opacity.as_ref()).collect();
    assert_eq!(masked.len(), 3, "three masked materials");
    let methods: Vec<Method> = ["mis", "best", "nee"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    // Light reaches much of the scene through masks only by the null interactions' chain (the
    // shadow rays do not see through), a rarer event with a heavier tail than in the other
    // fixtures: 4096 samples per pixel, and for `nee` (uniform directions, no MIS) 4x4 blocks.
    // (At 1024 spp, `best` with seeds from 5300 passed 99.59% of channels; at 32768 spp, `mis`
    // against the reference's variance alone stays within |z| 3.3 on every 2x2 block.)
    let plan = |m: &Method| if m.name() == "nee" { (4096, 4) } else { (4096, 2) };
    agrees_with_reference(&reference, &scene, &methods, plan, 2300, Preset::Mis.method());
}

#[test]
fn opacities_are_read_as_mitsuba_reads_them() {
    let scene = Scene::load(fixture()).unwrap();
    let by_kind = |f: &dyn Fn(&Opacity) -> bool| scene.materials.iter().filter_map(|m| m.opacity.as_ref()).find(|o| f(o)).cloned().unwrap();
    // An <rgb> opacity: its channels' mean (Mitsuba's eval_1 of a constant).
    let constant = by_kind(&|o| matches!(o, Opacity::Constant(_)));
    assert!(matches!(constant, Opacity::Constant(c) if (c - 0.4).abs() < 1e-12), "{constant:?}");
    // A checkerboard: each colour's channel mean (0.9 and 0.15), at uvs of either colour, the
    // colours in each other's places as Mitsuba 3.9.1's eval_1 has them (color0 where the
    // fractional parts of u and v are on different sides of 1/2).
    let checker = by_kind(&|o| matches!(o, Opacity::Texture(pathlab::scene::Texture::Checkerboard { .. })));
    assert!((checker.eval([0.05, 0.05], [0.0; 3]) - 0.15).abs() < 1e-6, "{}", checker.eval([0.05, 0.05], [0.0; 3]));
    assert!((checker.eval([0.25, 0.05], [0.0; 3]) - 0.9).abs() < 1e-6, "{}", checker.eval([0.25, 0.05], [0.0; 3]));
    // A bitmap: the luminance of its linear RGB.
    let bitmap = by_kind(&|o| matches!(o, Opacity::Texture(pathlab::scene::Texture::Bitmap(_))));
    let Opacity::Texture(t) = &bitmap else { unreachable!() };
    let rgb = t.eval([0.3, 0.5], [0.0; 3]);
    let y = 0.212671 * rgb[0] + 0.715160 * rgb[1] + 0.072169 * rgb[2];
    assert!((bitmap.eval([0.3, 0.5], [0.0; 3]) - y).abs() < 1e-6);
    // A mask without opacity takes Mitsuba's 0.5; an opacity of 1 is no mask (the same hash as
    // none).
    let xml = xml_with_bsdf("<bsdf type=\"mask\" id=\"m\"><bsdf type=\"diffuse\"/></bsdf>", "m");
    let s = load_xml(&xml, "m.xml").unwrap();
    assert_eq!(s.materials[0].opacity, Some(Opacity::Constant(0.5)));
    let opaque = Scene::parse(&toml_with_material("diffuse = 0.5\nopacity = 1"), "a.toml").unwrap();
    let none = Scene::parse(&toml_with_material("diffuse = 0.5"), "a.toml").unwrap();
    assert_eq!(opaque.materials[0].opacity, None);
    assert_eq!(opaque.content_hash(), none.content_hash());
    let half = Scene::parse(&toml_with_material("diffuse = 0.5\nopacity = 0.5"), "a.toml").unwrap();
    assert_ne!(half.content_hash(), none.content_hash());
}

#[test]
fn convert_writes_the_masks_and_their_textures() {
    let dir = tempfile::tempdir().unwrap();
    let (toml, _) = pathlab::scene::mitsuba::to_toml(&fixture(), &[], dir.path()).unwrap();
    // The <rgb> opacity as its channels' mean, the textures as tables.
    assert!(toml.contains("opacity = 0.39999"), "{toml}");
    assert_eq!(toml.matches(".opacity]\n").count(), 2, "{toml}");
    assert!(toml.contains("texture = \"checkerboard\"") && toml.contains("texture = \"bitmap\""), "{toml}");
    let path = dir.path().join("mask.toml");
    std::fs::write(&path, &toml).unwrap();
    let from_toml = Scene::load(&path).unwrap();
    let from_xml = Scene::load(fixture()).unwrap();
    assert_eq!(from_toml.content_hash(), from_xml.content_hash());
}

#[test]
fn bad_masks_are_refused_where_they_are() {
    let refused = |text: &str, file: &str| -> String {
        let loaded = if file.ends_with(".xml") { load_xml(text, file) } else { Scene::parse(text, file) };
        match loaded {
            Ok(_) => panic!("accepted:\n{text}"),
            Err(e) => e.to_string(),
        }
    };
    let e = refused(&toml_with_material("diffuse = 0.5\nopacity = 1.5"), "a.toml");
    assert!(e.contains("materials.m.opacity") && e.contains("in [0, 1]"), "{e}");
    let e = refused(&toml_with_material("diffuse = 0.5\nopacity = \"half\""), "a.toml");
    assert!(e.contains("materials.m.opacity"), "{e}");
    let e = refused(&toml_with_material("diffuse = 0.5\nopacity = { texture = \"bitmap\", filename = \"nowhere.png\" }"), "a.toml");
    assert!(e.contains("materials.m.opacity") && e.contains("nowhere.png"), "{e}");
    // Mitsuba: exactly one nested BSDF, and no mask in a mask.
    let e = refused(&xml_with_bsdf("<bsdf type=\"mask\" id=\"m\"><float name=\"opacity\" value=\"0.3\"/></bsdf>", "m"), "m.xml");
    assert!(e.contains("m.xml:3:") && e.contains("needs the <bsdf> it masks"), "{e}");
    let e = refused(&xml_with_bsdf("<bsdf type=\"mask\" id=\"m\"><bsdf type=\"diffuse\"/><bsdf type=\"diffuse\"/></bsdf>", "m"), "m.xml");
    assert!(e.contains("one nested <bsdf>"), "{e}");
    let e = refused(
        &xml_with_bsdf("<bsdf type=\"mask\" id=\"m\"><bsdf type=\"twosided\"><bsdf type=\"mask\"><bsdf type=\"diffuse\"/></bsdf></bsdf></bsdf>", "m"),
        "m.xml",
    );
    assert!(e.contains("a mask inside"), "{e}");
    // A mask inside a twosided: Mitsuba refuses it (a null lobe is a transmission component).
    let e = refused(&xml_with_bsdf("<bsdf type=\"twosided\" id=\"m\"><bsdf type=\"mask\"><bsdf type=\"diffuse\"/></bsdf></bsdf>", "m"), "m.xml");
    assert!(e.contains("a mask inside a <bsdf type=\"twosided\">"), "{e}");
    let e = refused(&xml_with_bsdf("<bsdf type=\"mask\" id=\"m\"><float name=\"opacity\" value=\"2\"/><bsdf type=\"diffuse\"/></bsdf>", "m"), "m.xml");
    assert!(e.contains("opacity") && e.contains("in [0, 1]"), "{e}");
    let e = refused(&xml_with_bsdf("<bsdf type=\"mask\" id=\"m\"><float name=\"alpha\" value=\"2\"/><bsdf type=\"diffuse\"/></bsdf>", "m"), "m.xml");
    assert!(e.contains("`alpha`") && e.contains("opacity"), "{e}");
}
