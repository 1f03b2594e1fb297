//! Conductors on the GPU: a smooth conductor's delta lobe under every method (a mirror of index
//! eta + i k shows the constant environment times Mitsuba's Fresnel term, computed here in f64),
//! light seen only in a mirror found by every light strategy (next event estimation cannot
//! follow a delta lobe, so emission found through it counts in full), a one-sided rough
//! conductor black from behind, bad conductor parameters refused, and Mitsuba's named conductors
//! (`material`) read from TOML and XML as its table (src/scene/bsdfs/named_conductors.rs,
//! generated from Mitsuba 3.9.1 itself by scripts/named_conductors.py).
//! Textured `eta` and `k` (tests/fixtures/textured_conductors/: a smooth conductor with
//! checkerboard eta and k, a rough one with a checkerboard eta) against Mitsuba 3.9.1 loading
//! the same file (48x48, 65536 spp with the variance of its mean; made by
//! scripts/xml_fixture_reference.sh), `mis`, `best` and `mis+ndf`, z-tested on 2x2 blocks as
//! tests/cornell_box.rs does.
//! (The microfacet lobes' sampling is tested in tests/chi2_sampling.rs; whole images against
//! Mitsuba in tests/veach_mis.rs.)

use crate::common;

use common::*;
use pathlab::method::{BsdfSampling, LightSampling, Method, MicrofacetSampling, Preset};
use pathlab::scene::{Scene, SceneError};
use pathlab::stats::z_test;

/// Mitsuba's fresnel_conductor (fresnel.h), in f64: the reference for the kernel's f32 one.
fn fresnel_conductor(cos_i: f64, eta: f64, k: f64) -> f64 {
    let c2 = cos_i * cos_i;
    let s2 = 1.0 - c2;
    let s4 = s2 * s2;
    let temp_1 = eta * eta - k * k - s2;
    let a2pb2 = (temp_1 * temp_1 + 4.0 * k * k * eta * eta).max(0.0).sqrt();
    let a = (0.5 * (a2pb2 + temp_1)).max(0.0).sqrt();
    let term_1 = a2pb2 + c2;
    let term_2 = 2.0 * cos_i * a;
    let r_s = (term_1 - term_2) / (term_1 + term_2);
    let term_3 = a2pb2 * c2 + s4;
    let term_4 = term_2 * s2;
    let r_p = r_s * (term_3 - term_4) / (term_3 + term_4);
    0.5 * (r_s + r_p)
}

const FRESNEL_KERNEL: &str = r#"
@group(0) @binding(0) var<storage, read> queries: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> results: array<vec4f>;

@compute @workgroup_size(64)
fn fresnel_kernel(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x;
    if (i >= arrayLength(&queries)) {
        return;
    }
    let q = queries[i];
    results[i] = vec4f(fresnel_conductor(q.x, vec3f(q.y), vec3f(q.z)), 0.0);
}
"#;

/// The kernel's conductor Fresnel term against Mitsuba's formula in f64, to 2e-6 (relative)
/// wherever it is evaluated, metals with an index of almost no real part among them (Mitsuba's
/// `none`, eta 0 + 1i, reflects everything). Written as Mitsuba writes it, a^2 = (|z| + t) / 2
/// cancels there: f32 left a residue whose root put F off by up to 4e-4 on lavapipe (eta 2e-4)
/// and, through a GPU's rounded sqrt, F(none) at 1 - 5.2e-4 on an NVIDIA H200.
#[test]
fn the_conductor_fresnel_term_holds_where_the_real_index_vanishes() {
    let mut queries: Vec<[f32; 4]> = Vec::new();
    for eta in [0.0f32, 5e-5, 1e-4, 2e-4, 3e-4, 1e-3, 0.200438, 1.5, 3.0] {
        for k in [0.0f32, 0.5, 1.0, 2.0, 3.91295] {
            for angle in [0.0f64, 30.0, 60.0, 80.0, 89.0] {
                queries.push([angle.to_radians().cos() as f32, eta, k, 0.0]);
            }
        }
    }
    // No material at all (eta = k = 0) is 0 / 0 at normal incidence, in the formula as in f64.
    queries.retain(|q| !(q[1] == 0.0 && q[2] == 0.0));
    let got = run_test_kernel(&pathlab::shaders::LIBRARY, FRESNEL_KERNEL, "fresnel_kernel", vec![(0, bytemuck::cast_slice(&queries).to_vec())], queries.len(), 1);
    for (q, g) in queries.iter().zip(got.iter().map(|v| v[0])) {
        let expected = fresnel_conductor(q[0] as f64, q[1] as f64, q[2] as f64);
        let err = (g as f64 - expected).abs() / expected;
        assert!(err <= 2e-6, "cos {} eta {} k {}: F = {g}, Mitsuba's formula in f64 gives {expected} ({err:.1e} relative)", q[0], q[1], q[2]);
    }
}

/// Every BSDF strategy and light strategy: the delta lobe is sampled whatever they are.
fn all_strategies() -> Vec<Method> {
    let mut methods: Vec<Method> = Preset::ALL.iter().map(|p| p.method()).collect();
    for bsdf in [BsdfSampling::UniformSphere, BsdfSampling::UniformHemisphere, BsdfSampling::Cosine] {
        methods.push(Method { bsdf, lights: LightSampling::MisBalance, ..Preset::Mis.method() });
    }
    methods.push(Method { microfacet: MicrofacetSampling::Ndf, ..Preset::Mis.method() });
    methods
}

#[test]
fn a_mirror_shows_the_environment_times_the_fresnel_term_for_every_method() {
    // Copper's index at the three channels (Bitterli's Veach scene), and a perfect mirror.
    let (eta, k) = ([0.200438, 0.924033, 1.10221], [3.91295, 2.45285, 2.14219]);
    for angle in [0.0f64, 30.0, 60.0, 80.0, 89.0] {
        let t = angle.to_radians();
        // One pixel, a 1e-3 degree field of view: one direction, at `angle` from the normal +y.
        let text = format!(
            "[camera]\nposition = [0, 1, 0]\nlook_at = [{:.12}, {:.12}, 0]\nup = [0, 0, 1]\nfov_x = 1e-3\n\
             [render]\nwidth = 1\nheight = 1\nmax_depth = 2\nenvironment = 0.5\n\
             [materials.copper]\nbsdf = \"conductor\"\neta = {eta:?}\nk = {k:?}\nspecular_reflectance = 0.8\ntwo_sided = false\n\
             [[rectangles]]\nmaterial = \"copper\"\ntransform = {{ rotate = {{ axis = [1, 0, 0], angle = -90 }}, scale = 1000 }}\n",
            t.sin(),
            1.0 - t.cos()
        );
        let s = scene(&text);
        for method in all_strategies() {
            let film = render(&s, method, 4, 1);
            for c in 0..3 {
                let expected = 0.5 * 0.8 * fresnel_conductor(t.cos(), eta[c], k[c]);
                let got = film.mean[0][c] as f64;
                assert!((got - expected).abs() <= 2e-4 * expected, "{angle} degrees, {}: channel {c} is {got}, Mitsuba's Fresnel term gives {expected}", method.name());
            }
        }
    }
}

#[test]
fn light_seen_only_in_a_mirror_is_found_by_every_light_strategy() {
    // A camera looking down at a perfect mirror that reflects a sphere light it cannot see
    // directly (the light is behind it). Next event estimation from the mirror's vertex
    // contributes nothing (a delta lobe), so the emission found through the mirror must count
    // in full for `nee` as for the others. Each image is z-tested against `plain` at 4x4 blocks
    // (Šidák over the file's channels at alpha = 0.01, at least 99.75% of them passing).
    let text = "[camera]\nposition = [0, 2, 0]\nlook_at = [0, 0, -2]\nup = [0, 1, 0]\nfov_x = 60\n\
                [render]\nwidth = 32\nheight = 32\nmax_depth = 3\n\
                [materials.mirror]\nbsdf = \"conductor\"\n[materials.lamp]\nemission = 4\n[materials.grey]\ndiffuse = 0.5\n\
                [[spheres]]\ncenter = [0, 1.5, -6]\nradius = 1\nmaterial = \"lamp\"\n\
                [[spheres]]\ncenter = [1.5, 0.5, -2]\nradius = 0.5\nmaterial = \"grey\"\n\
                [[rectangles]]\nmaterial = \"mirror\"\ntransform = { rotate = { axis = [1, 0, 0], angle = -90 }, scale = 50 }\n";
    let s = scene(text);
    let reference = render(&s, Preset::Plain.method(), 4096, 7).downsample(4);
    let methods = [Preset::Nee.method(), Preset::Mis.method(), Preset::Best.method(), Method { lights: LightSampling::MisBalance, ..Preset::Mis.method() }];
    let mean: f64 = reference.mean.iter().map(|p| p[0] as f64).sum::<f64>() / reference.mean.len() as f64;
    assert!(mean > 0.01, "the mirror shows no light (mean {mean})");
    for (k, method) in methods.iter().enumerate() {
        let film = render(&s, *method, 1024, 20 + k as u32).downsample(4);
        let t = z_test(&reference, &film, 0.01 / methods.len() as f64);
        assert!(t.pass_fraction >= 0.9975, "{}: {t:?}", method.name());
    }
}

#[test]
fn bad_conductor_parameters_are_refused_naming_the_field() {
    let base = "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 60\n\
                [render]\nwidth = 4\nheight = 4\nmax_depth = 2\nenvironment = 1\n";
    let cases = [
        ("bsdf = \"roughconductor\"\nalpha = 0", "materials.m.alpha", "alpha must be > 0"),
        ("bsdf = \"roughconductor\"\nalpha = -0.5", "materials.m.alpha", "alpha must be > 0"),
        ("bsdf = \"roughconductor\"\nalpha = nan", "materials.m.alpha", "finite"),
        ("bsdf = \"roughconductor\"\ndistribution = \"phong\"", "materials.m.distribution", "unknown distribution"),
        ("bsdf = \"conductor\"\ndiffuse = 0.5", "materials.m.diffuse", "belongs to bsdf = \"phong\""),
        ("bsdf = \"conductor\"\nalpha = 0.1", "materials.m.alpha", "belongs to bsdf = \"roughconductor\""),
        ("alpha = 0.1", "materials.m.alpha", "not a field of a phong material"),
        ("bsdf = \"velvet\"", "materials.m.bsdf", "unknown bsdf"),
        ("bsdf = \"conductor\"\neta = -1", "materials.m.eta", ">= 0"),
        // Fields of no kind, and of the wrong type, name the field and what it should be.
        ("shininess = 3", "materials.m.shininess", "unknown field `shininess` of a phong material (its fields: diffuse, specular, glossiness"),
        ("bsdf = \"conductor\"\neta = \"gold\"", "materials.m.eta", "must be a number or an array of 3 numbers"),
        ("bsdf = \"roughconductor\"\nalpha = [0.1, 0.2]", "materials.m.alpha", "must be a number"),
    ];
    for (material, field, message) in cases {
        let text = format!("{base}[materials.m]\n{material}\n[[spheres]]\ncenter = [0, 0, -3]\nradius = 1\nmaterial = \"m\"\n");
        match Scene::parse(&text, "c.toml") {
            Err(SceneError::Invalid(d)) => {
                let d = &d[0];
                assert!(d.field == field && d.message.contains(message) && d.line >= 1, "{material}: {d}");
            }
            other => panic!("{material}: accepted ({:?})", other.map(|s| s.materials[0].clone())),
        }
    }
    // Mitsuba clamps alpha to 1e-4; so does pathlab, saying so.
    let text = format!("{base}[materials.m]\nbsdf = \"roughconductor\"\nalpha = 1e-6\n[[spheres]]\ncenter = [0, 0, -3]\nradius = 1\nmaterial = \"m\"\n");
    let s = Scene::parse(&text, "c.toml").unwrap();
    assert!(matches!(&s.materials[0].bsdf, pathlab::scene::Bsdf::RoughConductor(r) if r.roughness.alpha == 1e-4));
    assert!(s.warnings.iter().any(|w| w.message.contains("clamped")));
}

#[test]
fn a_one_sided_rough_conductor_is_black_from_behind() {
    // A camera under a one-sided rough conductor facing up, against a white environment:
    // it sees the back, which reflects nothing; twosided, it reflects.
    let text = |two_sided: bool| {
        format!(
            "[camera]\nposition = [0, -1, 0]\nlook_at = [0.2, 0, 0.1]\nup = [0, 0, 1]\nfov_x = 30\n\
             [render]\nwidth = 8\nheight = 8\nmax_depth = 2\nenvironment = 1\n\
             [materials.m]\nbsdf = \"roughconductor\"\ndistribution = \"ggx\"\nalpha = 0.3\ntwo_sided = {two_sided}\n\
             [[rectangles]]\nmaterial = \"m\"\ntransform = {{ rotate = {{ axis = [1, 0, 0], angle = -90 }}, scale = 100 }}\n"
        )
    };
    for method in [Preset::Plain.method(), Preset::Mis.method()] {
        let back = render(&scene(&text(false)), method, 16, 3);
        assert!(back.mean.iter().flatten().all(|&x| x == 0.0), "{}: the back of a one-sided conductor reflects", method.name());
        let front = render(&scene(&text(true)), method, 64, 3);
        let mean = front.mean.iter().flatten().map(|&x| x as f64).sum::<f64>() / (3 * front.mean.len()) as f64;
        assert!(mean > 0.5, "{}: a twosided rough conductor of F = 1 reflects only {mean} of a white environment", method.name());
    }
}

/// `material = "Au"` (TOML) and `<string name="material" value="Au"/>` (XML, both conductors) give
/// the complex index of Mitsuba's table, "none" a perfect mirror; every material Mitsuba's
/// conductor documentation lists is there, spelt as Mitsuba spells it.
#[test]
fn named_conductors_are_mitsubas() {
    use pathlab::scene::{Bsdf, Conductor, NAMED_CONDUCTORS};
    // Mitsuba's documented presets (conductor.cpp's table), one per measured material.
    let documented = [
        "a-C", "Ag", "Al", "AlAs", "AlSb", "Au", "Be", "Cr", "CsI", "Cu", "Cu2O", "CuO", "d-C", "Hg", "HgTe", "Ir", "K", "Li", "MgO", "Mo",
        "Na_palik", "Nb", "Ni_palik", "Rh", "Se", "SiC", "SnTe", "Ta", "Te", "ThF4", "TiC", "TiN", "TiO2", "VC", "V_palik", "VN", "W",
    ];
    for name in documented {
        assert!(Conductor::named(name).is_some(), "{name} missing");
    }
    assert_eq!(NAMED_CONDUCTORS.len(), 71);
    let (au_eta, au_k) = Conductor::named("Au").unwrap();
    assert_eq!((au_eta.x, au_k.z), (0.14303598, 1.6033592));

    let with = toml_with_material;
    let s = scene(&with("bsdf = \"conductor\"\nmaterial = \"Au\"\nspecular_reflectance = 0.9"));
    assert!(matches!(&s.materials[0].bsdf, Bsdf::Conductor(c) if (c.eta, c.k) == (au_eta, au_k) && c.reflectance.x == 0.9));
    let s = scene(&with("bsdf = \"roughconductor\"\nmaterial = \"none\"\nalpha = 0.2"));
    assert!(matches!(&s.materials[0].bsdf, Bsdf::RoughConductor(r) if r.fresnel.eta == glam::DVec3::ZERO && r.fresnel.k == glam::DVec3::ONE));
    for (material, message) in [
        ("bsdf = \"conductor\"\nmaterial = \"gold\"", "unknown conductor \"gold\" (Mitsuba's named conductors: Ag, Al, AlAs"),
        ("bsdf = \"conductor\"\nmaterial = \"Cu\"\nk = 2", "give either `material` or `eta` and `k`, not both"),
    ] {
        match Scene::parse(&with(material), "c.toml") {
            Err(SceneError::Invalid(d)) => assert!(d[0].field == "materials.m.material" && d[0].message.contains(message), "{material}: {}", d[0]),
            other => panic!("{material}: accepted ({:?})", other.map(|s| s.materials[0].clone())),
        }
    }

    let dir = std::env::temp_dir().join(format!("pathlab-named-conductors-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("c.xml");
    std::fs::write(
        &path,
        "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"45\"/>\
         <film type=\"hdrfilm\"><integer name=\"width\" value=\"4\"/><integer name=\"height\" value=\"4\"/></film></sensor>\n\
         <bsdf type=\"roughconductor\" id=\"al\"><string name=\"material\" value=\"Al\"/><float name=\"alpha\" value=\"0.05\"/></bsdf>\n\
         <bsdf type=\"conductor\" id=\"cu\"><string name=\"material\" value=\"Cu\"/></bsdf>\n\
         <shape type=\"sphere\"><ref id=\"al\"/></shape>\n<shape type=\"sphere\"><point name=\"center\" x=\"3\" y=\"0\" z=\"0\"/><ref id=\"cu\"/></shape>\n</scene>\n",
    )
    .unwrap();
    let s = Scene::load(&path).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    let al = Conductor::named("Al").unwrap();
    let cu = Conductor::named("Cu").unwrap();
    assert!(s.materials.iter().any(|m| matches!(&m.bsdf, Bsdf::RoughConductor(r) if (r.fresnel.eta, r.fresnel.k) == al && r.roughness.alpha == 0.05)));
    assert!(s.materials.iter().any(|m| matches!(&m.bsdf, Bsdf::Conductor(c) if (c.eta, c.k) == cu)));
}

#[test]
fn negative_eta_and_k_of_a_mitsuba_conductor_read_as_their_magnitudes() {
    // Bitterli's living room (ReSTIR_GI_DR's living-room-2) gives a roughconductor's eta and k
    // negative channels, which Mitsuba accepts; its Fresnel term, as pathlab's, reads them only
    // squared. Read as their magnitudes, with a warning naming the line: the same scene as the
    // magnitudes written out.
    let bsdf = |eta: &str, k: &str| {
        xml_with_bsdf(&format!("<bsdf type=\"roughconductor\" id=\"c\"><rgb name=\"eta\" value=\"{eta}\"/><rgb name=\"k\" value=\"{k}\"/></bsdf>"), "c")
    };
    let negative = load_xml(&bsdf("-0.0485226, 4.14275, 4.66977", "-0.0363742, 0.0937665, 1.30074"), "c.xml").unwrap();
    let positive = load_xml(&bsdf("0.0485226, 4.14275, 4.66977", "0.0363742, 0.0937665, 1.30074"), "c.xml").unwrap();
    assert_eq!(negative.content_hash(), positive.content_hash());
    let warnings: Vec<String> = negative.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(warnings.iter().filter(|w| w.contains("c.xml:3:") && w.contains("below 0")).count(), 2, "{warnings:?}");
    // Not finite: refused.
    let e = load_xml(&bsdf("nan, 1, 1", "1, 1, 1"), "c.xml").unwrap_err().to_string();
    assert!(e.contains("`eta`"), "{e}");
}

#[test]
fn textured_eta_and_k_agree_with_mitsuba() {
    let reference = mitsuba_fixture("textured_conductors");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/textured_conductors/textured_conductors.xml"), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let textured: Vec<usize> = scene.materials.iter().map(|m| m.bsdf.textures().len()).filter(|&n| n > 0).collect();
    assert_eq!(textured, [2, 1], "eta and k of the smooth one, eta of the rough one");
    // `convert` writes the textures as TOML tables, which load as the same scene.
    let dir = tempfile::tempdir().unwrap();
    let (toml, _) = pathlab::scene::mitsuba::to_toml(scene.path.as_path(), &defines, dir.path()).unwrap();
    std::fs::write(dir.path().join("c.toml"), &toml).unwrap();
    assert_eq!(Scene::load(dir.path().join("c.toml")).unwrap().content_hash(), scene.content_hash());
    let methods = [Preset::Mis.method(), Preset::Best.method(), Method { microfacet: MicrofacetSampling::Ndf, ..Preset::Mis.method() }];
    agrees_with_reference(&reference, &scene, &methods, |_| (1024, 2), 2300, Preset::Mis.method());
}
