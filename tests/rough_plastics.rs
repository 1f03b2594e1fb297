//! Mitsuba's `roughplastic` (src/scene/bsdfs/rough_plastic.rs, shaders/bsdfs/rough_plastic.wgsl).
//! Its sampling (both lobe selections, both microfacet strategies, the generic strategies) is
//! chi-square tested in tests/chi2_sampling.rs; its coating tables' quadrature by the unit tests
//! of rough_plastic.rs.
//!
//! 1. The kernel's f and pdf against Mitsuba 3.9.1's own `eval` and `pdf`
//!    (tests/fixtures/roughplastic_evals.json, made by scripts/roughplastic_evals.py) at 36 pairs
//!    of directions from normal to grazing incidence for four plastics (both distributions,
//!    alpha 0.02 to 0.6, linear and nonlinear, indices 1.49 to 2.419 / 1.33), and reciprocity.
//!    f within 1e-3 (relative, or 1e-6 absolute; measured: 5.3e-4 at most): the coating tables
//!    are the same integrals as Mitsuba's, by another quadrature, and interpolated the same way.
//!    The pdf within 5e-3 (measured: 3e-3): Mitsuba's 32^2-node quadrature leaves its
//!    transmittance off by up to ~2e-4 (GGX, alpha 0.3, normal incidence: pathlab's table gives
//!    0.952180107, a 2-million-point integral over the normals' angle 0.9521801078; Mitsuba's f
//!    and pdf put its own about 2.3e-4 lower), which moves the lobe probability by 0.5%; and
//!    Beckmann's visible-normal pdf is given with the exact G1 (the density pathlab samples)
//!    where Mitsuba's uses the rational fit.
//! 2. The Cornell box with two rough plastics (tests/fixtures/cornell_rough_plastic/:
//!    Mitsuba's default Beckmann coating with a red base, and a nonlinear GGX coating of alpha
//!    0.3 in `bk7` with a specular reflectance of 0.8) against Mitsuba 3.9.1 loading the same
//!    file (64x64, 65536 spp in 64 passes with the per-pixel variance of its mean;
//!    scripts/cornell_rough_plastic_reference.sh), z-tested on blocks as tests/cornell_box.rs
//!    does (at least 99.75% of channels passing; `mis` scaled by 1.05 is rejected), for `mis`,
//!    `best`, `mis+fixed` (the fixed lobe selection), `mis+ndf` (normals from the distribution)
//!    and `nee` (uniform directions). Fails falsely with probability below 0.01.
//! 3. Bad roughplastic parameters are refused naming the field (TOML) or line and column (XML).

use crate::common;

use common::*;
use glam::DVec3;
use pathlab::method::{LobeSelection, MicrofacetSampling, Method, Preset};
use pathlab::names::Named;
use pathlab::scene::{Bsdf, Distribution, Plastic, RoughPlastic, Scene, SceneError};

#[test]
fn the_rough_plastic_evaluates_as_mitsubas_and_is_reciprocal() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/roughplastic_evals.json");
    let fixture: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    assert_eq!(fixture["mitsuba"], "3.9.1");
    let configs = fixture["configs"].as_array().unwrap();
    assert_eq!(configs.len(), 4);
    for c in configs {
        let distribution = Distribution::from_name(c["distribution"].as_str().unwrap()).unwrap();
        let layers = Plastic {
            diffuse: DVec3::from(json_v3(&c["diffuse"])),
            diffuse_texture: None,
            specular: DVec3::from(json_v3(&c["specular"])),
            int_ior: c["int_ior"].as_f64().unwrap(),
            ext_ior: c["ext_ior"].as_f64().unwrap(),
            nonlinear: c["nonlinear"].as_bool().unwrap(),
        };
        let p = RoughPlastic { layers, distribution, alpha: c["alpha"].as_f64().unwrap() };
        agrees_with_mitsuba_evals(&Bsdf::RoughPlastic(p.clone()), c["pairs"].as_array().unwrap(), &format!("{p:?}"), (1e-3, 1e-6), (5e-3, 1e-6));
    }
}

/// Light sampling with material sampling at 2x2 blocks; with uniform directions beside next
/// event estimation, 8x8 blocks.
fn plan(method: &Method) -> (u64, u32) {
    if method.lights == pathlab::method::LightSampling::Mis {
        (1024, 2)
    } else {
        (2048, 8)
    }
}

#[test]
fn mis_best_fixed_lobes_ndf_and_nee_agree_with_mitsuba_on_two_rough_plastics_in_the_cornell_box() {
    let reference = mitsuba_fixture("cornell_rough_plastic");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene =
        Scene::load_with(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/cornell_rough_plastic/cornell_rough_plastic.xml"), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let kinds: Vec<&Bsdf> = scene.materials.iter().map(|m| &m.bsdf).filter(|b| matches!(b, Bsdf::RoughPlastic(_))).collect();
    assert_eq!(kinds.len(), 2, "two rough plastics");
    let fixed = Method { lobes: LobeSelection::Fixed, ..Preset::Mis.method() };
    let ndf = Method { microfacet: MicrofacetSampling::Ndf, ..Preset::Mis.method() };
    let methods = [Preset::Mis.method(), Preset::Best.method(), fixed, ndf, Preset::Nee.method()];
    agrees_with_reference(&reference, &scene, &methods, plan, 1400, Preset::Mis.method());
}

#[test]
fn rough_plastic_parameters_are_read_and_bad_ones_refused() {
    let with = toml_with_material;
    // Mitsuba's defaults: Beckmann, alpha 0.1, diffuse 0.5 under polypropylene in air.
    let s = scene(&with("bsdf = \"roughplastic\""));
    let expected = RoughPlastic {
        layers: Plastic { diffuse: DVec3::splat(0.5), diffuse_texture: None, specular: DVec3::ONE, int_ior: 1.49, ext_ior: 1.000277, nonlinear: false },
        distribution: Distribution::Beckmann,
        alpha: 0.1,
    };
    assert_eq!(s.materials[0].bsdf, Bsdf::RoughPlastic(expected));
    let s = scene(&with("bsdf = \"roughplastic\"\ndistribution = \"ggx\"\nalpha = 0.3\nint_ior = \"bk7\"\nnonlinear = true"));
    assert!(matches!(&s.materials[0].bsdf, Bsdf::RoughPlastic(p) if p.alpha == 0.3 && p.distribution == Distribution::Ggx && p.layers.int_ior == 1.5046 && p.layers.nonlinear));

    let cases = [
        ("bsdf = \"roughplastic\"\nalpha = 0", "materials.m.alpha", "alpha must be > 0"),
        ("bsdf = \"roughplastic\"\ndistribution = \"phong\"", "materials.m.distribution", "unknown distribution"),
        ("bsdf = \"roughplastic\"\nint_ior = \"unobtainium\"", "materials.m.int_ior", "unknown index of refraction"),
        ("bsdf = \"roughplastic\"\neta = 1.5", "materials.m.eta", "belongs to"),
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

    // Mitsuba's XML: anisotropic roughness is refused at its line and column, as Mitsuba does.
    let xml = |bsdf: &str| xml_with_bsdf(bsdf, "p");
    let dir = std::env::temp_dir().join(format!("pathlab-roughplastic-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("p.xml");
    std::fs::write(&path, xml("<bsdf type=\"roughplastic\" id=\"p\"><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha\" value=\"0.2\"/><string name=\"int_ior\" value=\"acrylic glass\"/></bsdf>")).unwrap();
    let s = Scene::load(&path).unwrap();
    assert!(matches!(&s.materials[0].bsdf, Bsdf::RoughPlastic(p) if p.alpha == 0.2 && p.distribution == Distribution::Ggx && p.layers.int_ior == 1.49), "{:?}", s.materials[0].bsdf);
    std::fs::write(&path, xml("<bsdf type=\"roughplastic\" id=\"p\"><float name=\"alpha_u\" value=\"0.1\"/><float name=\"alpha_v\" value=\"0.2\"/></bsdf>")).unwrap();
    let e = Scene::load(&path).unwrap_err().to_string();
    assert!(e.contains("p.xml:3:") && e.contains("has one `alpha`"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}
