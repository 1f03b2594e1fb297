//! Mitsuba's area emitter with a textured `radiance` (`Material::emission_texture`, looked up by
//! `triangle_emission` in shaders/emitters/triangle.wgsl): a hit's uv where a ray meets the
//! light, the sampled point's uv (from its barycentrics) where next event estimation picks it.
//!
//! 1. tests/fixtures/textured_lights/textured_lights.xml (a bitmap light and a checkerboard
//!    light above a floor and a sphere) rendered by `mis`, `nee+all+solid-angle` (every light
//!    sample's radiance is a sampled point's lookup) and `plain` (every light is met by a ray:
//!    a hit's lookup) is z-tested against Mitsuba 3.9.1 rendering the same file (64x48, 65536
//!    spp in 64 passes with the per-pixel variance of its mean; WIDTH=64 HEIGHT=48
//!    scripts/xml_fixture_reference.sh tests/fixtures/textured_lights/textured_lights.xml), on
//!    blocks as tests/cornell_box.rs does (at least 99.75% of channels passing, Šidák-corrected:
//!    fails falsely with probability below 0.01; `mis` scaled by 1.05 is rejected).
//! 2. A texture that is one value everywhere (a `rawconstant`) renders the untextured light's
//!    image bit for bit: the lookup adds nothing else (no sample dimension, no other light
//!    selection).
//! 3. The TOML field and the XML plugin are read as Mitsuba reads them, and what pathlab does not
//!    support is refused by name.

use crate::common;

use common::*;
use pathlab::method::{Method, Preset};
use pathlab::scene::{Scene, SceneError, Texture};

fn fixture() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/textured_lights/textured_lights.xml")
}

#[test]
fn textured_lights_agree_with_mitsuba() {
    let reference = mitsuba_fixture("textured_lights");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(fixture(), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.materials.iter().filter(|m| m.emission_texture.is_some()).count(), 2, "two textured lights");
    let methods: Vec<Method> = ["mis", "nee+all+solid-angle", "plain"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    let plan = |m: &Method| if m.name() == "plain" { (4096, 4) } else { (1024, 4) };
    agrees_with_reference(&reference, &scene, &methods, plan, 4700, Preset::Mis.method());
}

/// A floor under a tilted quad light emitting `emission` (a TOML value), seen by the camera.
fn quad_light_scene(emission: &str) -> String {
    format!(
        "[camera]\nposition = [0, 2, 3]\nlook_at = [0, 0.3, 0]\nup = [0, 1, 0]\nfov_x = 50\n\
         [render]\nwidth = 24\nheight = 18\nmax_depth = 3\n\
         [materials.floor]\ndiffuse = 0.5\n[materials.lamp]\ndiffuse = 0\nemission = {emission}\n\
         [[rectangles]]\nmaterial = \"floor\"\ntransform = {{ scale = 3, rotate = {{ axis = [1, 0, 0], angle = -90 }} }}\n\
         [[rectangles]]\nmaterial = \"lamp\"\ntransform = {{ scale = 0.6, rotate = {{ axis = [1, 0, 0], angle = 60 }}, translate = [0.2, 1.2, 0] }}\n"
    )
}

#[test]
fn a_constant_emission_texture_renders_the_untextured_image_bit_for_bit() {
    let plain = Scene::parse(&quad_light_scene("[4, 3, 2]"), "plain.toml").unwrap();
    let textured = Scene::parse(&quad_light_scene("{ texture = \"rawconstant\", value = [4, 3, 2] }"), "textured.toml").unwrap();
    assert!(textured.materials.iter().any(|m| m.emission_texture.is_some()));
    assert_ne!(plain.content_hash(), textured.content_hash());
    for (k, method) in ["mis", "plain"].iter().enumerate() {
        let method = Method::from_name(method).unwrap();
        let (a, b) = (render(&plain, method, 16, 4710 + k as u32), render(&textured, method, 16, 4710 + k as u32));
        assert!(a.mean.iter().any(|p| p[0] > 0.0), "{}: the light is seen", method.name());
        assert_eq!(bits(&a), bits(&b), "{}: a constant texture changes the image", method.name());
    }
}

#[test]
fn textured_emission_is_read_as_mitsuba_reads_it_and_bad_ones_refused() {
    let scene = Scene::load(fixture()).unwrap();
    // The bitmap's light: its texture, and for light selection its mean (radiance.exr's pixels:
    // R = 1 + 2x + y/2, G = 1/2 + 5y/2 + x/4, B 9 or 1/4 in a checker, over 4 x 3 pixels).
    let bitmap = scene.materials.iter().find(|m| matches!(m.emission_texture, Some(Texture::Bitmap(_)))).unwrap();
    assert!((bitmap.emission - glam::DVec3::new(4.5, 3.375, 4.625)).abs().max_element() < 1e-6, "{:?}", bitmap.emission);
    let checker = scene.materials.iter().find(|m| matches!(m.emission_texture, Some(Texture::Checkerboard { .. }))).unwrap();
    let at = |uv: [f32; 2]| checker.emission_texture.as_ref().unwrap().eval(uv, [0.0; 3]);
    assert_eq!((at([0.05, 0.05]), at([0.2, 0.05])), ([0.9, 0.8, 0.6], [0.05, 0.1, 0.2]));

    // TOML: `emission` a texture table; the hash changes with it.
    let toml = |emission: &str, shape: &str| {
        format!(
            "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 60\n\
             [render]\nwidth = 4\nheight = 4\nmax_depth = 2\n\
             [materials.lamp]\ndiffuse = 0\nemission = {emission}\n{shape}"
        )
    };
    let rectangle = "[[rectangles]]\nmaterial = \"lamp\"\ntransform = { translate = [0, 0, -2] }\n";
    let checkerboard = |c0: f64| format!("{{ texture = \"checkerboard\", color0 = {c0}, color1 = 0.5, to_uv_scale = [4, 4] }}");
    let a = Scene::parse(&toml(&checkerboard(3.0), rectangle), "a.toml").unwrap();
    let b = Scene::parse(&toml(&checkerboard(2.0), rectangle), "b.toml").unwrap();
    assert!((a.materials[0].emission - glam::DVec3::splat(1.75)).abs().max_element() < 1e-12, "the mean: {:?}", a.materials[0].emission);
    assert_ne!(a.content_hash(), b.content_hash());
    let sphere = "[[spheres]]\ncenter = [0, 0, -3]\nradius = 1\nmaterial = \"lamp\"\n";
    let disk = "[[disks]]\nmaterial = \"lamp\"\ntransform = { translate = [0, 0, -2] }\n";
    let volume = "{ texture = \"volume\", filename = \"no.vol\" }";
    let cases = [
        (toml(&checkerboard(3.0), sphere), "spheres[0].material", "triangle meshes"),
        (toml(&checkerboard(3.0), disk), "disks[0].material", "triangle meshes"),
        (toml(volume, rectangle), "materials.lamp.emission", ""),
        (toml("{ texture = \"rawconstant\", value = -1 }", rectangle), "materials.lamp.emission", ">= 0"),
        (toml("{ color0 = 1 }", rectangle), "materials.lamp.emission", "texture ="),
    ];
    for (text, field, message) in cases {
        match Scene::parse(&text, "c.toml") {
            Err(SceneError::Invalid(d)) => assert!(d.iter().any(|d| d.field == field && d.message.contains(message) && d.line >= 1), "{text}: {d:?}"),
            other => panic!("{text}: accepted ({:?})", other.map(|s| s.materials.clone())),
        }
    }

    // XML: a texture named other than `radiance` is refused at its line and column.
    let xml = "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><film type=\"hdrfilm\"><integer name=\"width\" value=\"4\"/><integer name=\"height\" value=\"4\"/></film></sensor>\n\
               <shape type=\"rectangle\"><emitter type=\"area\"><texture name=\"irradiance\" type=\"checkerboard\"/></emitter></shape>\n</scene>\n";
    let e = load_xml(xml, "t.xml").unwrap_err().to_string();
    assert!(e.contains("t.xml:3:") && e.contains("its textured property is `radiance`"), "{e}");

    // convert writes the textures as the TOML field, which reads back to the same scene.
    let dir = tempfile::tempdir().unwrap();
    let (toml_text, _) = pathlab::scene::mitsuba::to_toml(&fixture(), &[], dir.path()).unwrap();
    assert!(toml_text.contains("texture = \"bitmap\"") && toml_text.contains("texture = \"checkerboard\""), "{toml_text}");
    let path = dir.path().join("textured_lights.toml");
    std::fs::write(&path, &toml_text).unwrap();
    let back = Scene::load(&path).unwrap();
    assert_eq!(back.materials.iter().filter(|m| m.emission_texture.is_some()).count(), 2);
    assert_eq!(back.content_hash(), scene.content_hash(), "the round trip keeps the scene");
}
