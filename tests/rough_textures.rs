//! Textured roughness: a roughconductor's or roughdielectric's `alpha` given as a texture
//! (`distribution::Roughness`, a scalar texture slot resolved by `scalar_texture_slot` in
//! shaders/texture.wgsl), read as Mitsuba's `eval_1`. tests/fixtures/rough_textures/
//! rough_textures.xml (a gold sphere with a checkerboard alpha, a GGX glass pane with a bitmap
//! alpha, before a chequered wall) rendered by `mis`, `best` and `mis+ndf` is z-tested against
//! Mitsuba 3.9.1 rendering the same file (48x48, 65536 spp in 64 passes with the per-pixel
//! variance of its mean; scripts/xml_fixture_reference.sh
//! tests/fixtures/rough_textures/rough_textures.xml), on 2x2 blocks as tests/cornell_box.rs does
//! (at least 99.75% of channels passing, Šidák-corrected: fails falsely with probability below
//! 0.01; `mis` scaled by 1.05 is rejected). The same scene with each roughness replaced by its
//! mean is rejected.

use crate::common;

use common::*;
use pathlab::method::{Method, Preset};
use pathlab::scene::{Bsdf, Scene, Texture};

fn fixture() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/rough_textures/rough_textures.xml")
}

#[test]
fn textured_roughness_agrees_with_mitsuba() {
    let reference = mitsuba_fixture("rough_textures");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(fixture(), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let methods: Vec<Method> = ["mis", "best", "mis+ndf"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    // 2048 spp: the glass pane's and the gold's sharp caustics on the wall and floor have heavy tails.
    agrees_with_reference(&reference, &scene, &methods, |_| (2048, 2), 2600, Preset::Mis.method());

    // Each roughness its texture's mean: rejected.
    let mut flat = scene.clone();
    for m in &mut flat.materials {
        match &mut m.bsdf {
            Bsdf::RoughConductor(r) => r.roughness.texture = None,
            Bsdf::RoughDielectric(r) => r.roughness.texture = None,
            _ => {}
        }
    }
    let film = render(&flat, Preset::Mis.method(), 1024, 2700);
    let z = pathlab::stats::z_test(&reference.downsample(2), &film.downsample(2), 0.01);
    assert!(z.pass_fraction < 0.9975, "the mean roughness passes: {:.4} of channels", z.pass_fraction);
}

#[test]
fn textured_roughness_is_read_and_refused_where_mitsuba_refuses_it() {
    let scene = Scene::load(fixture()).unwrap();
    let conductor = scene.materials.iter().find_map(|m| match &m.bsdf {
        Bsdf::RoughConductor(r) => Some(r.clone()),
        _ => None,
    });
    let t = conductor.unwrap().roughness.texture.unwrap();
    // Mitsuba's eval_1 of the checkerboard: channel means, color0 (0.03) where eval gives color1.
    assert!(matches!(t, Texture::Checkerboard { .. }));
    assert!((t.eval_1([0.05, 0.05], [0.0; 3]) - 0.4).abs() < 1e-6, "{}", t.eval_1([0.05, 0.05], [0.0; 3]));
    assert!((t.eval_1([0.2, 0.05], [0.0; 3]) - 0.03).abs() < 1e-6, "{}", t.eval_1([0.2, 0.05], [0.0; 3]));
    // The pipeline looks up only the slots some material textures (`TEXTURED_<KIND>`): the
    // conductor's alpha (its fourth slot, after eta, k and specular_reflectance) and the dielectric's
    // alpha (its third, after specular_reflectance and specular_transmittance); the diffuse
    // wall's reflectance.
    let f = pathlab::gpu::SceneFeatures::of(&scene);
    let slots = |k: pathlab::scene::BsdfKind| f.textured_slots[k.constant() as usize];
    assert_eq!(slots(pathlab::scene::BsdfKind::RoughConductor), 0b1000);
    assert_eq!(slots(pathlab::scene::BsdfKind::RoughDielectric), 0b100);
    assert_eq!(slots(pathlab::scene::BsdfKind::Phong), 0b1);
    assert_eq!(slots(pathlab::scene::BsdfKind::Plastic), 0);
    // TOML: a texture table as alpha; convert writes it, and it loads as the same scene.
    let dir = tempfile::tempdir().unwrap();
    let (toml, _) = pathlab::scene::mitsuba::to_toml(&fixture(), &[], dir.path()).unwrap();
    let path = dir.path().join("r.toml");
    std::fs::write(&path, &toml).unwrap();
    assert_eq!(Scene::load(&path).unwrap().content_hash(), scene.content_hash());
    // roughplastic's alpha is a number (Mitsuba precomputes its coating for one roughness).
    let e = Scene::parse(&toml_with_material("bsdf = \"roughplastic\"\nalpha = { texture = \"checkerboard\" }"), "a.toml").unwrap_err().to_string();
    assert!(e.contains("materials.m.alpha") && e.contains("must be a number"), "{e}");
    let xml = xml_with_bsdf("<bsdf type=\"roughplastic\" id=\"t\"><texture type=\"checkerboard\" name=\"alpha\"/></bsdf>", "t");
    let e = load_xml(&xml, "t.xml").unwrap_err().to_string();
    assert!(e.contains("t.xml:3:") && e.contains("textured `alpha`"), "{e}");
}
