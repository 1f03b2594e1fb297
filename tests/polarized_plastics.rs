//! Mitsuba's `pplastic` (src/scene/bsdfs/polarized_plastic.rs, shaders/bsdfs/
//! polarized_plastic.wgsl) and its null-flagged `polarizer` and `null` (read as an index-matched
//! thin dielectric, src/scene/bsdfs/thin_dielectric.rs), as Mitsuba 3.9.1's RGB variants render
//! them. pplastic's sampling is chi-square tested with the other routines
//! (tests/chi2_sampling.rs, `polarized_plastic_routines`).
//!
//! 1. The kernel's f and pdf against Mitsuba's own `eval` and `pdf` (tests/fixtures/
//!    pplastic_evals.json, made by scripts/pplastic_evals.py) at 36 pairs of directions from
//!    normal to grazing incidence for three pplastics (both distributions, alpha 0.06 to 0.5,
//!    indices 1.33 to 1.6, a specular_reflectance below 1), and reciprocity. f within 1e-3
//!    relative (or 1e-6 absolute), the pdf within 5e-3 (Beckmann's visible-normal pdf is given
//!    with the exact G1, the density pathlab samples, where Mitsuba's uses the rational fit).
//! 2. tests/fixtures/pplastic/pplastic.xml (two pplastic spheres, an anisotropic pplastic floor,
//!    a polarizer sheet and a null sheet that blocks shadow rays) rendered by `mis`, `mis+ndf`
//!    and `nee` (uniform directions) z-tested against Mitsuba rendering the same file (64x48,
//!    65536 spp in 64 passes with the per-pixel variance of its mean; WIDTH=64 HEIGHT=48
//!    scripts/xml_fixture_reference.sh tests/fixtures/pplastic/pplastic.xml), on blocks as
//!    tests/cornell_box.rs does (at least 99.75% of channels passing, Šidák-corrected: fails
//!    falsely with probability below 0.01; `mis` scaled by 1.05 is rejected).
//! 3. Parameters are read as Mitsuba reads them, and bad ones refused naming the field (TOML)
//!    or line and column (XML).

use crate::common;

use common::*;
use glam::DVec3;
use pathlab::method::{MicrofacetSampling, Method, Preset};
use pathlab::names::Named;
use pathlab::scene::{Bsdf, Distribution, PolarizedPlastic, Roughness, Scene, SceneError};

fn fixture() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/pplastic/pplastic.xml")
}

#[test]
fn the_polarized_plastic_evaluates_as_mitsubas_and_is_reciprocal() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/pplastic_evals.json");
    let fixture: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    assert_eq!(fixture["mitsuba"], "3.9.1");
    let configs = fixture["configs"].as_array().unwrap();
    assert_eq!(configs.len(), 3);
    for c in configs {
        let p = PolarizedPlastic {
            diffuse: DVec3::from(json_v3(&c["diffuse"])),
            diffuse_texture: None,
            specular: DVec3::from(json_v3(&c["specular"])),
            eta: c["eta"].as_f64().unwrap(),
            distribution: Distribution::from_name(c["distribution"].as_str().unwrap()).unwrap(),
            roughness: Roughness::isotropic(c["alpha"].as_f64().unwrap()),
        };
        let (f, pdf) = agrees_with_mitsuba_evals(&Bsdf::PolarizedPlastic(p.clone()), c["pairs"].as_array().unwrap(), &format!("{p:?}"), (1e-3, 1e-6), (5e-3, 1e-6));
        println!("{:?} alpha {}: worst relative f {f:.2e}, pdf {pdf:.2e}", p.distribution, p.roughness.alpha);
    }
}

#[test]
fn pplastic_polarizer_and_null_agree_with_mitsuba() {
    let reference = mitsuba_fixture("pplastic");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(fixture(), &defines).unwrap();
    // The polarizer's one warning: polarisation is not modelled.
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    assert!(scene.warnings[0].message.contains("polarisation"), "{:?}", scene.warnings);
    let plastics = scene.materials.iter().filter(|m| matches!(m.bsdf, Bsdf::PolarizedPlastic(_))).count();
    assert_eq!(plastics, 3, "three pplastics");
    let ndf = Method { microfacet: MicrofacetSampling::Ndf, ..Preset::Mis.method() };
    let methods = [Preset::Mis.method(), ndf, Preset::Nee.method()];
    // The null sheet blocks the shadow rays to what is under it, which light reaches by
    // material sampling alone: a heavy tail (as with masks), under which one render's own
    // variance of its mean is too small where no rare sample happened to land. 2048 samples
    // per pixel on 4x4 blocks, and for `nee` (uniform directions, no MIS: the rarest hits) 8x8.
    // (On 2x2 blocks `mis+ndf` passed 99.74% of channels with max |z| 7.7; eight renders of it
    // at seeds 1-8 against their spread, not their own variance, stay within |z| 3.8 on every
    // 2x2 block.)
    let plan = |m: &Method| if m.name() == "nee" { (2048, 8) } else { (2048, 4) };
    agrees_with_reference(&reference, &scene, &methods, plan, 4500, Preset::Mis.method());
}

#[test]
fn pplastic_polarizer_and_null_are_read_as_mitsuba_reads_them() {
    let scene = Scene::load(fixture()).unwrap();
    let plastics: Vec<&PolarizedPlastic> =
        scene.materials.iter().filter_map(|m| if let Bsdf::PolarizedPlastic(p) = &m.bsdf { Some(p) } else { None }).collect();
    // Mitsuba's defaults: Beckmann, polypropylene (1.49) in air (1.000277), specular 1.
    let purple = plastics.iter().find(|p| p.roughness.alpha == 0.06).unwrap();
    assert_eq!(purple.distribution, Distribution::Beckmann);
    assert!((purple.eta - 1.49 / 1.000277).abs() < 1e-12 && purple.specular == DVec3::ONE);
    // `eta` given: the relative index itself.
    let ggx = plastics.iter().find(|p| p.roughness.alpha == 0.3).unwrap();
    assert!(ggx.distribution == Distribution::Ggx && ggx.eta == 1.6 && ggx.specular == DVec3::splat(0.8));
    // alpha_u and alpha_v: anisotropic, so hits carry tangent frames.
    let floor = plastics.iter().find(|p| p.roughness.is_anisotropic()).unwrap();
    assert_eq!((floor.roughness.alpha, floor.roughness.alpha_v), (0.05, Some(0.35)));
    // The polarizer and the null: index-matched panes passing 0.5 x 0.8 and everything, reflecting
    // nothing.
    let panes: Vec<_> = scene.materials.iter().filter_map(|m| if let Bsdf::ThinDielectric(d) = &m.bsdf { Some(d) } else { None }).collect();
    assert_eq!(panes.len(), 2);
    for d in &panes {
        assert!(d.int_ior == 1.0 && d.ext_ior == 1.0 && d.reflectance == DVec3::ZERO, "{d:?}");
    }
    let mut passes: Vec<f64> = panes.iter().map(|d| d.transmittance.x).collect();
    passes.sort_by(f64::total_cmp);
    assert!((passes[0] - 0.4).abs() < 1e-12 && passes[1] == 1.0, "{passes:?}");

    // TOML: Mitsuba's defaults, and bad values refused naming the field.
    let s = common::scene(&toml_with_material("bsdf = \"pplastic\""));
    let expected = PolarizedPlastic {
        diffuse: DVec3::splat(0.5),
        diffuse_texture: None,
        specular: DVec3::ONE,
        eta: 1.49 / 1.000277,
        distribution: Distribution::Beckmann,
        roughness: Roughness::isotropic(0.1),
    };
    assert_eq!(s.materials[0].bsdf, Bsdf::PolarizedPlastic(expected));
    let cases = [
        ("bsdf = \"pplastic\"\nalpha = 0", "materials.m.alpha", "alpha must be > 0"),
        ("bsdf = \"pplastic\"\nalpha = 0.1\nalpha_u = 0.1\nalpha_v = 0.2", "materials.m.alpha_u", "not both"),
        ("bsdf = \"pplastic\"\nint_ior = \"unobtainium\"", "materials.m.int_ior", "unknown index of refraction"),
        ("bsdf = \"pplastic\"\nnonlinear = true", "materials.m.nonlinear", "belongs to"),
    ];
    for (material, field, message) in cases {
        match Scene::parse(&toml_with_material(material), "p.toml") {
            Err(SceneError::Invalid(d)) => {
                let d = &d[0];
                assert!(d.field == field && d.message.contains(message) && d.line >= 1, "{material}: {d}");
            }
            other => panic!("{material}: accepted ({:?})", other.map(|s| s.materials[0].clone())),
        }
    }

    // XML: Mitsuba's constructor's refusals, at their line and column.
    let refused = [
        ("<bsdf type=\"pplastic\" id=\"p\"><float name=\"eta\" value=\"1.5\"/><float name=\"int_ior\" value=\"1.5\"/></bsdf>", "not both"),
        ("<bsdf type=\"pplastic\" id=\"p\"><float name=\"int_ior\" value=\"1.2\"/><float name=\"ext_ior\" value=\"1.2\"/></bsdf>", "must differ"),
        ("<bsdf type=\"pplastic\" id=\"p\"><boolean name=\"nonlinear\" value=\"true\"/></bsdf>", "nonlinear"),
        ("<bsdf type=\"polarizer\" id=\"p\"><texture name=\"transmittance\" type=\"checkerboard\"/></bsdf>", "textured `transmittance`"),
        ("<bsdf type=\"null\" id=\"p\"><float name=\"theta\" value=\"1\"/></bsdf>", "theta"),
    ];
    for (bsdf, message) in refused {
        let e = load_xml(&xml_with_bsdf(bsdf, "p"), "p.xml").unwrap_err().to_string();
        assert!(e.contains("p.xml:3:") && e.contains(message), "{bsdf}: {e}");
    }
}
