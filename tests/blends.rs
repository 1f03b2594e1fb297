//! Mitsuba's `blendbsdf` (`Material::blend`, src/scene/bsdfs/blend.rs, `blend_pick` in
//! shaders/scene.wgsl): f = (1 - w) f_0 + w f_1, one of the two BSDFs picked per path vertex.
//!
//! 1. tests/fixtures/blend/blend.xml (a checkerboard-weighted blend of a black GGX plastic and
//!    rough gold, a two-sided diffuse blended with rough glass, a twosided blend seen from
//!    behind, a mask around a blend) rendered by `mis`, `best` and `mis+ndf` is z-tested against
//!    Mitsuba 3.9.1 rendering the same file (64x48, 65536 spp in 64 passes with the per-pixel
//!    variance of its mean; WIDTH=64 HEIGHT=48 scripts/xml_fixture_reference.sh
//!    tests/fixtures/blend/blend.xml), on blocks as tests/cornell_box.rs does (at least 99.75%
//!    of channels passing, Šidák-corrected: fails falsely with probability below 0.01; `mis`
//!    scaled by 1.05 is rejected).
//! 2. Where Mitsuba's own image is off the blend's definition (a delta BSDF in a blend: its
//!    blendbsdf.cpp divides the delta lobe's weight by the other lobe's density), pathlab is
//!    tested against the definition: with one bounce (max_depth 2) the image is linear in f, so
//!    the image of a blend of a black GGX plastic and smooth gold by 0.3 must be 0.7 times the
//!    plastic's image plus 0.3 times the gold's (variances combined likewise), z-tested on 2x2
//!    blocks (fails falsely with probability below 0.01).
//! 3. The TOML fields and the XML plugin are read as Mitsuba reads them, and bad ones refused.

use crate::common;

use common::*;
use pathlab::method::{Method, Preset};
use pathlab::scene::{Opacity, Scene, SceneError};

fn fixture() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/blend/blend.xml")
}

#[test]
fn blends_agree_with_mitsuba() {
    let reference = mitsuba_fixture("blend");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(fixture(), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.materials.iter().filter(|m| m.blend.is_some()).count(), 4, "four blends");
    let methods: Vec<Method> = ["mis", "best", "mis+ndf"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    // Light reaches the floor under the glass sphere through it by material sampling alone (a
    // heavy tail): 2048 samples per pixel on 4x4 blocks. (`nee`'s uniform directions through
    // rough glass and off rough gold have tails too heavy for one render's own variance at any
    // affordable count: at 16384 spp its blocks there scatter from 0.81 to 1.43 of Mitsuba's,
    // both ways.)
    let plan = |_: &Method| (2048, 4);
    agrees_with_reference(&reference, &scene, &methods, plan, 4600, Preset::Mis.method());
}

/// A sphere of `bsdf` (one line of XML, or a blend's) under a rectangle light, above a floor,
/// with one bounce (max_depth 2): the image is linear in the sphere's BSDF.
fn one_bounce_scene(bsdf: &str) -> Scene {
    let xml = format!(
        r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="2"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 1, 4" target="0, 0.4, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="24"/><rfilter type="box"/></film>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale x="1.2" y="0.8" z="1"/><rotate x="1" angle="110"/><translate y="2.2" z="1.2"/></transform>
        <emitter type="area"><rgb name="radiance" value="6, 5, 4"/></emitter>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" x="0" y="0.5" z="0"/><float name="radius" value="0.5"/>
        {bsdf}
    </shape>
</scene>"#
    );
    load_xml(&xml, "one_bounce.xml").unwrap()
}

#[test]
fn a_blend_with_a_delta_bsdf_is_the_blend_of_its_two_images() {
    let plastic = r#"<bsdf type="roughplastic"><string name="distribution" value="ggx"/><float name="alpha" value="0.3"/><rgb name="diffuse_reflectance" value="0"/></bsdf>"#;
    let gold = r#"<bsdf type="conductor"><string name="material" value="Au"/></bsdf>"#;
    let blend = format!(r#"<bsdf type="blendbsdf"><float name="weight" value="0.3"/>{plastic}{gold}</bsdf>"#);
    let method = Preset::Mis.method();
    let spp = 4096;
    let [a, b, mixed] = [plastic, gold, blend.as_str()].map(|bsdf| render(&one_bounce_scene(bsdf), method, spp, 4610));
    // The definition's image, 0.7 a + 0.3 b, and the variance of its mean.
    let mut expected = a.clone();
    for i in 0..expected.mean.len() {
        for c in 0..3 {
            expected.mean[i][c] = 0.7 * a.mean[i][c] + 0.3 * b.mean[i][c];
            expected.variance[i][c] = 0.49 * a.variance[i][c] + 0.09 * b.variance[i][c];
        }
    }
    let z = pathlab::stats::z_test(&expected.downsample(2), &mixed.downsample(2), 0.01);
    let report = format!("{:.4} of {} channels pass |z| <= {:.2}; max |z| {:.2}, mean z {:+.3}", z.pass_fraction, z.channels, z.threshold, z.max_abs_z, z.mean_z);
    println!("{report}");
    assert!(z.pass_fraction >= 0.9975, "the blend's image is not 0.7 x the plastic's + 0.3 x the gold's: {report}");
    // Not vacuous: the gold's image differs from the plastic's on the sphere.
    let differ = pathlab::stats::z_test(&a.downsample(2), &b.downsample(2), 0.01);
    assert!(differ.pass_fraction < 0.9, "the two BSDFs' images hardly differ: {differ:?}");
}

#[test]
fn blends_are_read_as_mitsuba_reads_them_and_bad_ones_refused() {
    let scene = Scene::load(fixture()).unwrap();
    // The checkerboard weight: each colour's channel mean (0.1 and 0.9), at uvs of either colour.
    let checker = scene.materials.iter().filter_map(|m| m.blend.as_ref()).find(|b| b.weight.texture().is_some()).unwrap();
    let mut values = [checker.weight.eval([0.05, 0.05], [0.0; 3]), checker.weight.eval([0.2, 0.05], [0.0; 3])];
    values.sort_by(f32::total_cmp);
    assert!((values[0] - 0.1).abs() < 1e-6 && (values[1] - 0.9).abs() < 1e-6, "{values:?}");
    // A twosided around the blend makes both of its BSDFs two-sided; a twosided inside it only
    // the one it wraps.
    let green = scene.materials.iter().find(|m| m.blend.as_ref().is_some_and(|b| b.weight == Opacity::Constant(0.6))).unwrap();
    assert!(green.two_sided && scene.materials[green.blend.as_ref().unwrap().material].two_sided);
    // A mask wraps the blend: the blend's material carries the opacity, the blended one none.
    let masked = scene.materials.iter().find(|m| m.opacity.is_some()).unwrap();
    assert!(masked.blend.is_some() && scene.materials[masked.blend.as_ref().unwrap().material].opacity.is_none());

    // TOML: `blend` and `blend_weight`; the hash changes with the weight.
    let toml = |extra: &str| {
        format!(
            "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 60\n\
             [render]\nwidth = 4\nheight = 4\nmax_depth = 2\nenvironment = 1\n\
             [materials.m]\ndiffuse = 0.5\n{extra}\n[materials.gold]\nbsdf = \"conductor\"\nmaterial = \"Au\"\n\
             [[spheres]]\ncenter = [0, 0, -3]\nradius = 1\nmaterial = \"m\"\n"
        )
    };
    let s = Scene::parse(&toml("blend = \"gold\"\nblend_weight = 0.25"), "b.toml").unwrap();
    let b = s.materials[s.materials.iter().position(|m| m.name == "m").unwrap()].blend.clone().unwrap();
    assert_eq!((s.materials[b.material].name.as_str(), b.weight), ("gold", Opacity::Constant(0.25)));
    assert!(s.warnings.is_empty(), "a blended material is used: {:?}", s.warnings);
    let other = Scene::parse(&toml("blend = \"gold\"\nblend_weight = 0.5"), "b.toml").unwrap();
    assert_ne!(s.content_hash(), other.content_hash());
    let cases = [
        ("blend = \"gold\"", "materials.m.blend", "needs its `blend_weight`"),
        ("blend_weight = 0.5", "materials.m.blend_weight", "without `blend`"),
        ("blend = \"gold\"\nblend_weight = 1.5", "materials.m.blend_weight", "in [0, 1]"),
        ("blend = \"silver\"\nblend_weight = 0.5", "materials.m.blend", "no material \"silver\""),
        ("blend = \"m\"\nblend_weight = 0.5", "materials.m.blend", "itself"),
        ("blend = \"gold\"\nblend_weight = 0.5\nback = \"gold\"", "materials.m.blend", "not supported"),
    ];
    // A back with a blend of its own is refused too (the pick is made on the front material).
    let back_blends = toml("back = \"gold\"").replace("material = \"Au\"\n", "material = \"Au\"\nblend = \"m\"\nblend_weight = 0.5\n");
    match Scene::parse(&back_blends, "b.toml") {
        Err(SceneError::Invalid(d)) => assert!(d.iter().any(|d| d.field == "materials.m.back" && d.message.contains("no back, blend")), "{d:?}"),
        other => panic!("a back with a blend accepted ({:?})", other.map(|s| s.materials.clone())),
    }
    for (extra, field, message) in cases {
        match Scene::parse(&toml(extra), "b.toml") {
            Err(SceneError::Invalid(d)) => {
                assert!(d.iter().any(|d| d.field == field && d.message.contains(message) && d.line >= 1), "{extra}: {d:?}");
            }
            other => panic!("{extra}: accepted ({:?})", other.map(|s| s.materials.clone())),
        }
    }

    // XML: Mitsuba's constructor's refusals, at their line and column.
    let refused = [
        ("<bsdf type=\"blendbsdf\" id=\"b\"><bsdf type=\"diffuse\"/><bsdf type=\"diffuse\"/></bsdf>", "needs its `weight`"),
        ("<bsdf type=\"blendbsdf\" id=\"b\"><float name=\"weight\" value=\"0.5\"/><bsdf type=\"diffuse\"/></bsdf>", "two nested BSDFs"),
        (
            "<bsdf type=\"blendbsdf\" id=\"b\"><float name=\"weight\" value=\"0.5\"/><bsdf type=\"diffuse\"/><bsdf type=\"mask\"><bsdf type=\"diffuse\"/></bsdf></bsdf>",
            "must be one plain BSDF",
        ),
    ];
    for (bsdf, message) in refused {
        let e = load_xml(&xml_with_bsdf(bsdf, "b"), "b.xml").unwrap_err().to_string();
        assert!(e.contains("b.xml:3:") && e.contains(message), "{bsdf}: {e}");
    }

    // convert writes the blend as TOML fields, which read back to the same scene.
    let dir = tempfile::tempdir().unwrap();
    let (toml_text, _) = pathlab::scene::mitsuba::to_toml(&fixture(), &[], dir.path()).unwrap();
    assert_eq!(toml_text.matches("\nblend = ").count(), 4, "{toml_text}");
    let path = dir.path().join("blend.toml");
    std::fs::write(&path, &toml_text).unwrap();
    let back = Scene::load(&path).unwrap();
    assert_eq!(back.materials.iter().filter(|m| m.blend.is_some()).count(), 4);
}
