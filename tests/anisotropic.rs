//! Anisotropic roughness: Mitsuba's `alpha_u` and `alpha_v` of `roughconductor` and
//! `roughdielectric` (`distribution::Roughness::alpha_v`; `eval_microfacet_d_uv` and the other
//! `_uv` forms in shaders/microfacet.wgsl), placed on each shape by its dp/du (`Hit.tangent`,
//! `bsdf_frame` in shaders/bsdf.wgsl), and the principled BSDF's `anisotropic`.
//! tests/fixtures/anisotropic/anisotropic.xml (a turned sphere, a turned rectangle, a cylinder, a
//! disk, an OBJ square without uvs and a pane of rough glass, each anisotropic, and a principled
//! metal sphere with an anisotropic specular lobe) rendered by `mis`, `best` and `mis+ndf` is z-tested against Mitsuba
//! 3.9.1 rendering the same file (64x48, 65536 spp in 64 passes with the per-pixel variance of
//! its mean; scripts/xml_fixture_reference.sh tests/fixtures/anisotropic/anisotropic.xml), on 2x2
//! blocks as tests/cornell_box.rs does (at least 99.75% of channels passing, Šidák-corrected:
//! fails falsely with probability below 0.01; `mis` scaled by 1.05 is rejected). The same scene
//! with alpha_u and alpha_v in each other's places (the lobes turned by 90 degrees, what a frame
//! off by a quarter turn would give) is rejected.
//!
//! Textured alpha_u and alpha_v (Mitsuba's eval_1 of each at the hit; the kernel resolves them
//! as scalar texture slots): tests/fixtures/textured_anisotropy/textured_anisotropy.xml (carbon
//! fibre of two inverted checkerboards on a sphere, as mitsuba-data's documentation scene; gold
//! whose alpha_v is 0 on half its squares, which Mitsuba clamps to 1e-4; rough glass with a
//! textured alpha_u; a principled metal whose `anisotropic` is a checkerboard) is z-tested against Mitsuba 3.9.1 the same way (64x48, 65536 spp; `mis`
//! and `best`), and the same scene with each material's alpha_u and alpha_v swapped is
//! rejected.

use crate::common;

use common::*;
use pathlab::method::{Method, Preset};
use pathlab::scene::{Bsdf, Scene};

fn fixture() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/anisotropic/anisotropic.xml")
}

#[test]
fn anisotropic_roughness_agrees_with_mitsuba() {
    let reference = mitsuba_fixture("anisotropic");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(fixture(), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let methods: Vec<Method> = ["mis", "best", "mis+ndf"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (2048, 2), 2800, Preset::Mis.method());

    // alpha_u and alpha_v swapped on every material: rejected.
    let mut swapped = scene.clone();
    for m in &mut swapped.materials {
        let r = match &mut m.bsdf {
            Bsdf::RoughConductor(c) => &mut c.roughness,
            Bsdf::RoughDielectric(d) => &mut d.roughness,
            _ => continue,
        };
        let v = r.alpha_v.unwrap();
        r.alpha_v = Some(r.alpha);
        r.alpha = v;
    }
    let film = render(&swapped, Preset::Mis.method(), 2048, 2900);
    let z = pathlab::stats::z_test(&reference.downsample(2), &film.downsample(2), 0.01);
    println!("alpha_u and alpha_v swapped (2048 spp, 2x2 blocks): {:.4} of channels pass", z.pass_fraction);
    assert!(z.pass_fraction < 0.9975, "alpha_u and alpha_v swapped pass: {:.4} of channels", z.pass_fraction);
}

#[test]
fn anisotropic_roughness_is_read_and_refused_where_mitsuba_refuses_it() {
    let scene = Scene::load(fixture()).unwrap();
    let sphere = scene.materials.iter().find_map(|m| match &m.bsdf {
        Bsdf::RoughConductor(c) if c.distribution == pathlab::scene::Distribution::Ggx => Some(c.roughness.clone()),
        _ => None,
    });
    let r = sphere.unwrap();
    assert_eq!((r.alpha, r.alpha_v), (0.05, Some(0.4)));
    assert!(r.is_anisotropic());
    // The principled sphere's anisotropic specular lobe.
    assert!(scene.materials.iter().any(|m| matches!(&m.bsdf, Bsdf::Principled(p) if p.anisotropic.value == 0.85)));
    // Tangent frames and the anisotropic formulas only where a material needs them.
    assert!(pathlab::gpu::SceneFeatures::of(&scene).anisotropic_roughness);
    assert!(!pathlab::gpu::SceneFeatures::of(&study_scene()).anisotropic_roughness);
    let rough = Scene::load(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/rough_textures/rough_textures.xml")).unwrap();
    assert!(!pathlab::gpu::SceneFeatures::of(&rough).anisotropic_roughness);

    // `convert` writes alpha_u and alpha_v, and the TOML loads as the same scene.
    let dir = tempfile::tempdir().unwrap();
    let (toml, _) = pathlab::scene::mitsuba::to_toml(&fixture(), &[], dir.path()).unwrap();
    assert!(toml.contains("alpha_u") && toml.contains("alpha_v"), "{toml}");
    let path = dir.path().join("a.toml");
    std::fs::write(&path, &toml).unwrap();
    assert_eq!(Scene::load(&path).unwrap().content_hash(), scene.content_hash());

    // Mitsuba's rules: both or neither, not with alpha; roughplastic has one alpha.
    let xml = |bsdf: &str| xml_with_bsdf(bsdf, "b");
    let refused = |text: String, wants: &[&str]| {
        let e = load_xml(&text, "a.xml").unwrap_err().to_string();
        assert!(e.contains("a.xml:3:") && wants.iter().all(|w| e.contains(w)), "{e}");
    };
    refused(xml("<bsdf type=\"roughconductor\" id=\"b\"><float name=\"alpha_u\" value=\"0.1\"/></bsdf>"), &["alpha_v", "both"]);
    refused(xml("<bsdf type=\"roughdielectric\" id=\"b\"><float name=\"alpha_u\" value=\"0.1\"/><float name=\"alpha_v\" value=\"0.2\"/><float name=\"alpha\" value=\"0.2\"/></bsdf>"), &["either `alpha` or"]);
    refused(xml("<bsdf type=\"roughconductor\" id=\"b\"><float name=\"alpha_u\" value=\"0\"/><float name=\"alpha_v\" value=\"0.2\"/></bsdf>"), &["alpha_u", "> 0"]);
    refused(xml("<bsdf type=\"roughplastic\" id=\"b\"><float name=\"alpha_u\" value=\"0.1\"/><float name=\"alpha_v\" value=\"0.2\"/></bsdf>"), &["alpha_u", "one `alpha`"]);
    // A textured alpha_u (or alpha_v) is read: tests below.
    let textured = load_xml(&xml("<bsdf type=\"roughconductor\" id=\"b\"><texture type=\"checkerboard\" name=\"alpha_u\"/><float name=\"alpha_v\" value=\"0.2\"/></bsdf>"), "a.xml").unwrap();
    assert!(textured.materials[0].bsdf.is_anisotropic());
    let toml_refused = |material: &str, wants: &[&str]| {
        let e = Scene::parse(&toml_with_material(material), "a.toml").unwrap_err().to_string();
        assert!(wants.iter().all(|w| e.contains(w)), "{e}");
    };
    toml_refused("bsdf = \"roughconductor\"\nalpha_u = 0.1", &["materials.m", "both `alpha_u` and `alpha_v`"]);
    toml_refused("bsdf = \"roughconductor\"\nalpha = 0.1\nalpha_u = 0.1\nalpha_v = 0.3", &["either `alpha` or"]);
    toml_refused("bsdf = \"roughplastic\"\nalpha_u = 0.1\nalpha_v = 0.3", &["alpha_u"]);
    // Equal alphas are the isotropic material: the same pipeline as `alpha`.
    let equal = Scene::parse(&toml_with_material("bsdf = \"roughconductor\"\nalpha_u = 0.2\nalpha_v = 0.2"), "a.toml").unwrap();
    assert!(!pathlab::gpu::SceneFeatures::of(&equal).anisotropic_roughness);

    // A researcher's microfacet technique of one alpha (the contract's first pair) is refused on
    // this scene, the error naming the pair of two (tests/techniques.rs proves one of those here).
    let technique = pathlab::scene::Technique::from_spec(&format!("bsdf:{}/examples/techniques/ggx_bounded_vndf.wgsl", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let e = pathlab::technique::check(gpu(), &technique, &scene, Default::default(), |_, _, _| {}).unwrap_err().to_string();
    assert!(e.contains("anisotropic roughness") && e.contains("one alpha") && e.contains("sample_microfacet_uv_technique"), "{e}");
}

fn textured_fixture() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/textured_anisotropy/textured_anisotropy.xml")
}

#[test]
fn textured_anisotropic_roughness_agrees_with_mitsuba() {
    let reference = mitsuba_fixture("textured_anisotropy");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(textured_fixture(), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let methods: Vec<Method> = ["mis", "best"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (2048, 2), 3700, Preset::Mis.method());

    // alpha_u and alpha_v (numbers and textures) swapped on every material: rejected.
    let mut swapped = scene.clone();
    for m in &mut swapped.materials {
        let r = match &mut m.bsdf {
            Bsdf::RoughConductor(c) => &mut c.roughness,
            Bsdf::RoughDielectric(d) => &mut d.roughness,
            _ => continue,
        };
        let (v, tv) = (r.alpha_v.unwrap(), r.texture_v.take());
        r.alpha_v = Some(r.alpha);
        r.texture_v = r.texture.take();
        r.alpha = v;
        r.texture = tv;
    }
    let film = render(&swapped, Preset::Mis.method(), 2048, 3800);
    let z = pathlab::stats::z_test(&reference.downsample(2), &film.downsample(2), 0.01);
    println!("textured alpha_u and alpha_v swapped (2048 spp, 2x2 blocks): {:.4} of channels pass", z.pass_fraction);
    assert!(z.pass_fraction < 0.9975, "alpha_u and alpha_v swapped pass: {:.4} of channels", z.pass_fraction);
}

#[test]
fn textured_anisotropic_roughness_is_read_and_written() {
    let scene = Scene::load(textured_fixture()).unwrap();
    let roughness: Vec<pathlab::scene::Roughness> = scene
        .materials
        .iter()
        .filter_map(|m| match &m.bsdf {
            Bsdf::RoughConductor(c) => Some(c.roughness.clone()),
            Bsdf::RoughDielectric(d) => Some(d.roughness.clone()),
            _ => None,
        })
        .collect();
    // Carbon (both textured), gold (alpha_v textured), glass (alpha_u textured); a texture's
    // alpha is its mean.
    assert_eq!(roughness.iter().map(|r| (r.texture.is_some(), r.texture_v.is_some())).collect::<Vec<_>>(), [(true, true), (false, true), (true, false)]);
    assert!(roughness.iter().all(|r| r.is_anisotropic()));
    assert!((roughness[0].alpha - 0.175).abs() < 1e-12 && roughness[1].alpha == 0.3, "{roughness:?}");
    assert!(scene.materials.iter().any(|m| matches!(&m.bsdf, Bsdf::Principled(p) if p.anisotropic.texture.is_some() && (p.anisotropic.value - 0.5).abs() < 1e-12)));
    let f = pathlab::gpu::SceneFeatures::of(&scene);
    assert!(f.anisotropic_roughness && f.has_uvs);
    // Principled's `anisotropic` is its ninth scalar texture slot (bit 8, after base_color and
    // the seven weights): more than the 8 bits a kind had in the features before.
    assert_eq!(f.textured_slots[pathlab::scene::BsdfKind::Principled.constant() as usize], 1 << 8);
    // The conductor's alpha_v slot is textured on both conductors (bit 4: after its three colour
    // slots and alpha).
    assert!(scene.materials.iter().all(|m| !matches!(m.bsdf, Bsdf::RoughConductor(_)) || m.bsdf.textured_slots() & 16 != 0));

    // `convert` writes the textures, and the TOML loads as the same scene.
    let dir = tempfile::tempdir().unwrap();
    let (toml, _) = pathlab::scene::mitsuba::to_toml(&textured_fixture(), &[], dir.path()).unwrap();
    assert!(toml.contains(".alpha_u]") && toml.contains(".alpha_v]"), "{toml}");
    let path = dir.path().join("t.toml");
    std::fs::write(&path, &toml).unwrap();
    assert_eq!(Scene::load(&path).unwrap().content_hash(), scene.content_hash());

    // roughplastic keeps one alpha.
    let e = Scene::parse(&toml_with_material("bsdf = \"roughplastic\"\nalpha_u = { texture = \"checkerboard\" }\nalpha_v = 0.3"), "a.toml").unwrap_err().to_string();
    assert!(e.contains("alpha_u"), "{e}");
}
