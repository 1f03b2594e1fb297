//! Mitsuba's smooth `plastic` (src/scene/bsdfs/plastic.rs, shaders/bsdfs/plastic.wgsl) and the
//! named indices of refraction (src/scene/bsdfs/ior.rs). Its lobe choice and both lobes'
//! sampling, under its own and the generic strategies, are chi-square tested in
//! tests/chi2_sampling.rs.
//!
//! 1. The kernel's f against Mitsuba's formula (plastic.cpp) computed here in f64, and
//!    reciprocity f(wi, wo) = f(wo, wi), at pairs of directions from normal to grazing, for
//!    linear and nonlinear plastics of several indices (exact checks to 1e-5, relative).
//! 2. The Cornell box with two plastics (tests/fixtures/cornell_plastic/cornell_plastic.xml:
//!    Mitsuba's defaults with a red base, and a nonlinear `bk7` coating with a specular
//!    reflectance of 0.8) against Mitsuba 3.9.1 loading the same file (64x64, 65536 spp in 64
//!    passes with the per-pixel variance of its mean; scripts/cornell_plastic_reference.sh),
//!    z-tested on blocks as tests/cornell_box.rs does (at least 99.75% of channels passing; `mis`
//!    scaled by 1.05 is rejected), for `mis`, `best`, `mis+fixed` (the fixed lobe selection),
//!    `nee` (uniform directions) and `cosine` (the generic strategies, which must leave the delta
//!    lobe to the plastic's own choice).
//!    Fails falsely with probability below 0.01.
//! 3. Bad plastic parameters and index names are refused naming the field (TOML) or the
//!    line and column (XML), listing the known names.

use crate::common;

use common::*;
use glam::DVec3;
use pathlab::method::{LobeSelection, Method, Preset};
use pathlab::scene::bsdfs::fresnel_diffuse_reflectance;
use pathlab::scene::{Bsdf, Plastic, Scene, SceneError};

/// Fresnel's reflectance of unpolarised light from outside (cos_i > 0), in f64.
fn fresnel(cos_i: f64, eta: f64) -> f64 {
    let sin_t2 = (1.0 - cos_i * cos_i) / (eta * eta);
    if eta == 1.0 {
        return 0.0;
    }
    if sin_t2 >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin_t2).sqrt();
    let a_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let a_p = (cos_t - eta * cos_i) / (cos_t + eta * cos_i);
    0.5 * (a_s * a_s + a_p * a_p)
}

/// Mitsuba's SmoothPlastic::eval divided by cos_o (pathlab's f has no cosine), in f64.
fn mitsuba_plastic_f(p: &Plastic, cos_i: f64, cos_o: f64) -> DVec3 {
    if cos_i <= 0.0 || cos_o <= 0.0 {
        return DVec3::ZERO;
    }
    let eta = p.eta();
    let fdr_int = fresnel_diffuse_reflectance(1.0 / eta);
    let denominator = if p.nonlinear { DVec3::ONE - p.diffuse * fdr_int } else { DVec3::splat(1.0 - fdr_int) };
    p.diffuse / denominator * (std::f64::consts::FRAC_1_PI / (eta * eta) * (1.0 - fresnel(cos_i, eta)) * (1.0 - fresnel(cos_o, eta)))
}

#[test]
fn the_plastic_evaluates_mitsubas_formula_and_is_reciprocal() {
    let plastics = [
        Plastic { diffuse: DVec3::splat(0.5), diffuse_texture: None, specular: DVec3::ONE, int_ior: 1.49, ext_ior: 1.000277, nonlinear: false },
        Plastic { diffuse: DVec3::new(0.9, 0.3, 0.05), diffuse_texture: None, specular: DVec3::splat(0.8), int_ior: 1.5046, ext_ior: 1.0, nonlinear: true },
        Plastic { diffuse: DVec3::new(0.2, 0.7, 0.4), diffuse_texture: None, specular: DVec3::ONE, int_ior: 2.419, ext_ior: 1.33, nonlinear: false },
    ];
    let angles = [0.0f64, 20.0, 45.0, 70.0, 85.0, 89.5];
    let dir = |theta: f64, phi: f64| {
        let (t, p) = (theta.to_radians(), phi.to_radians());
        [(t.sin() * p.cos()) as f32, (t.sin() * p.sin()) as f32, t.cos() as f32, 0.0f32]
    };
    let mut pairs: Vec<[f32; 4]> = Vec::new();
    for &a in &angles {
        for (k, &b) in angles.iter().enumerate() {
            pairs.push(dir(a, 10.0));
            pairs.push(dir(b, 200.0 + 17.0 * k as f64));
        }
    }
    let count = pairs.len() / 2;
    for p in &plastics {
        let out = eval_bsdf_pairs(&Bsdf::Plastic(p.clone()), &pairs);
        for i in 0..count {
            let (wo, wi) = (pairs[2 * i], pairs[2 * i + 1]);
            let expected = mitsuba_plastic_f(p, wo[2] as f64, wi[2] as f64);
            let (fwd, bwd) = (out[2 * i], out[2 * i + 1]);
            for c in 0..3 {
                let (got, back) = (fwd[c] as f64, bwd[c] as f64);
                assert!((got - expected[c]).abs() <= 1e-5 * expected[c], "{p:?} wo {wo:?} wi {wi:?}: f channel {c} is {got}, Mitsuba's formula gives {}", expected[c]);
                assert!((got - back).abs() <= 1e-6 * got.max(1e-30), "{p:?} wo {wo:?} wi {wi:?}: f(wi, wo) = {got} but f(wo, wi) = {back}");
            }
            // The own strategy's density: the cosine lobe's times the probability of not
            // drawing the delta lobe.
            let f_i = fresnel(wo[2] as f64, p.eta());
            let w = p.specular_sampling_weight();
            let prob_diffuse = (1.0 - f_i) * (1.0 - w) / (f_i * w + (1.0 - f_i) * (1.0 - w));
            let pdf = prob_diffuse * wi[2] as f64 * std::f64::consts::FRAC_1_PI;
            assert!((fwd[3] as f64 - pdf).abs() <= 1e-5 * pdf, "{p:?} wo {wo:?} wi {wi:?}: pdf {} instead of {pdf}", fwd[3]);
        }
    }
}

/// Light sampling with material sampling at 2x2 blocks; light or BSDF sampling alone are
/// noisier (the light is found by the cosine lobe's rays only, or by uniform ones beside next
/// event estimation): 8x8 blocks.
fn plan(method: &Method) -> (u64, u32) {
    if method.lights == pathlab::method::LightSampling::Mis {
        (1024, 2)
    } else {
        (2048, 8)
    }
}

#[test]
fn mis_best_fixed_lobes_nee_and_cosine_agree_with_mitsuba_on_two_plastics_in_the_cornell_box() {
    let reference = mitsuba_fixture("cornell_plastic");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/cornell_plastic/cornell_plastic.xml"), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let kinds: Vec<&Bsdf> = scene.materials.iter().map(|m| &m.bsdf).filter(|b| matches!(b, Bsdf::Plastic(_))).collect();
    assert_eq!(kinds.len(), 2, "two plastics");
    let fixed = Method { lobes: LobeSelection::Fixed, ..Preset::Mis.method() };
    let methods = [Preset::Mis.method(), Preset::Best.method(), fixed, Preset::Nee.method(), Preset::Cosine.method()];
    agrees_with_reference(&reference, &scene, &methods, plan, 1300, Preset::Mis.method());
}

#[test]
fn named_indices_are_read_from_toml_and_xml_and_unknown_ones_refused() {
    let with = toml_with_material;
    // Names in any case; Mitsuba's defaults where none is given.
    let s = scene(&with("bsdf = \"plastic\"\nint_ior = \"BK7\"\next_ior = \"water\"\nnonlinear = true"));
    assert_eq!(s.materials[0].bsdf, Bsdf::Plastic(Plastic { diffuse: DVec3::splat(0.5), diffuse_texture: None, specular: DVec3::ONE, int_ior: 1.5046, ext_ior: 1.333, nonlinear: true }));
    let s = scene(&with("bsdf = \"plastic\""));
    assert!(matches!(&s.materials[0].bsdf, Bsdf::Plastic(p) if p.int_ior == 1.49 && p.ext_ior == 1.000277 && !p.nonlinear));
    let s = scene(&with("bsdf = \"dielectric\"\nint_ior = \"diamond\""));
    assert!(matches!(&s.materials[0].bsdf, Bsdf::Dielectric(d) if d.int_ior == 2.419));

    let cases = [
        ("bsdf = \"plastic\"\nint_ior = \"unobtainium\"", "materials.m.int_ior", "unknown index of refraction \"unobtainium\" (known: vacuum, helium"),
        ("bsdf = \"dielectric\"\next_ior = \"glass\"", "materials.m.ext_ior", "known: vacuum"),
        ("bsdf = \"plastic\"\nint_ior = 0", "materials.m.int_ior", "must be an index of refraction > 0"),
        ("bsdf = \"plastic\"\ndiffuse_reflectance = -0.5", "materials.m.diffuse_reflectance", ">= 0"),
        ("bsdf = \"plastic\"\nnonlinear = 1", "materials.m.nonlinear", "must be true or false"),
        ("bsdf = \"plastic\"\ndiffuse = 0.5", "materials.m.diffuse", "belongs to bsdf = \"phong\""),
    ];
    for (material, field, message) in cases {
        match Scene::parse(&with(material), "p.toml") {
            Err(SceneError::Invalid(d)) => {
                let d = &d[0];
                assert!(d.field == field && d.message.contains(message) && d.line >= 1, "{material}: {d}");
            }
            other => panic!("{material}: accepted ({:?})", other.map(|s| s.materials[0].clone())),
        }
    }

    // Mitsuba's XML: a <string> index names a material; an unknown one is refused at its line
    // and column with the known names.
    let xml = |bsdf: &str| xml_with_bsdf(bsdf, "p");
    let dir = std::env::temp_dir().join(format!("pathlab-ior-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("p.xml");
    std::fs::write(&path, xml("<bsdf type=\"plastic\" id=\"p\"><string name=\"int_ior\" value=\"acrylic glass\"/><float name=\"ext_ior\" value=\"1.2\"/></bsdf>")).unwrap();
    let s = Scene::load(&path).unwrap();
    assert!(matches!(&s.materials[0].bsdf, Bsdf::Plastic(p) if p.int_ior == 1.49 && p.ext_ior == 1.2), "{:?}", s.materials[0].bsdf);
    std::fs::write(&path, xml("<bsdf type=\"dielectric\" id=\"p\"><string name=\"int_ior\" value=\"kryptonite\"/></bsdf>")).unwrap();
    let e = Scene::load(&path).unwrap_err().to_string();
    assert!(e.contains("p.xml:3:") && e.contains("unknown index of refraction \"kryptonite\" (known: vacuum,"), "{e}");
    std::fs::write(&path, xml("<bsdf type=\"plastic\" id=\"p\"><rgb name=\"diffuse_reflectance\" value=\"0.5\"/><float name=\"alpha\" value=\"0.1\"/></bsdf>")).unwrap();
    let e = Scene::load(&path).unwrap_err().to_string();
    assert!(e.contains("p.xml:3:") && e.contains("`alpha` of <bsdf type=\"plastic\"> is not supported"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The shipped scene of the README's lobe-selection study loads without warnings, with its
/// glass and its two plastics.
#[test]
fn the_glass_and_plastic_scene_loads() {
    let scene = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/glass_and_plastic.xml")).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let count = |kind: pathlab::scene::BsdfKind| scene.materials.iter().filter(|m| m.bsdf.kind() == kind).count();
    assert_eq!((count(pathlab::scene::BsdfKind::Plastic), count(pathlab::scene::BsdfKind::Dielectric)), (2, 1));
}
