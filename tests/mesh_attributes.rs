//! Mitsuba's `mesh_attribute` texture (`Texture::MeshAttribute`; `eval_mesh_attribute_texture`
//! in shaders/texture.wgsl): a named per-vertex or per-face attribute of a PLY mesh
//! (`mesh::MeshAttribute`, grouped by Mitsuba's naming rules in src/scene/mesh/ply.rs) as a BSDF
//! parameter, a vertex attribute interpolated by the hit's barycentrics.
//!
//! 1. tests/fixtures/mesh_attributes/mesh_attributes.xml (three copies of a 72-triangle grid,
//!    textured by its vertex colours, its face colours scaled, and a blend by its one-channel
//!    face weight) rendered by `mis` and `nee` is z-tested against Mitsuba 3.9.1 rendering the
//!    same file (64x48, 65536 spp in 64 passes with the per-pixel variance of its mean; WIDTH=64
//!    HEIGHT=48 scripts/xml_fixture_reference.sh tests/fixtures/mesh_attributes/mesh_attributes.xml),
//!    on blocks as tests/cornell_box.rs does (at least 99.75% of channels passing,
//!    Šidák-corrected: fails falsely with probability below 0.01; `mis` scaled by 1.05 is
//!    rejected).
//! 2. A face attribute that is one value everywhere renders the untextured material's image, to
//!    float rounding, on a mesh small enough for the unrolled tests (the kernel's other path to
//!    a triangle's barycentrics).
//! 3. The TOML field and the XML plugin are read as Mitsuba reads them, and what cannot be read
//!    is refused by name: a mesh without the attribute, a three-channel attribute read as one
//!    number, the texture on a sphere, a negative emission, a name without `vertex_` or `face_`.
//! 4. A mesh attribute as an area light's radiance, met by rays (`plain`) and sampled (`nee`),
//!    the two z-tested against each other (Mitsuba 3.9.1 mis-evaluates it in emitter sampling:
//!    see the test).

use crate::common;

use common::*;
use pathlab::method::{Method, Preset};
use pathlab::scene::{Scene, SceneError, Texture};

fn fixture() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/mesh_attributes/mesh_attributes.xml")
}

#[test]
fn mesh_attributes_agree_with_mitsuba() {
    let reference = mitsuba_fixture("mesh_attributes");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(fixture(), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.mesh_attribute_names(), vec!["face_color", "face_weight", "vertex_color"]);
    let methods: Vec<Method> = ["mis", "nee"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (1024, 4), 4800, Preset::Mis.method());
}

/// The fixture's grid as an area light whose radiance is its vertex colour times 3 (TOML),
/// tilted down towards the camera just above a floor, which fills most of the image and shows
/// the light's colours triangle by triangle near it.
fn attribute_light_scene() -> String {
    let grid = fixture().with_file_name("grid.ply");
    format!(
        "[camera]\nposition = [0, 1.1, 1.5]\nlook_at = [0, 0.1, -0.2]\nup = [0, 1, 0]\nfov_x = 55\n\
         [render]\nwidth = 32\nheight = 24\nmax_depth = 2\n\
         [materials.floor]\ndiffuse = 0.6\n\
         [materials.lamp]\ndiffuse = 0\nemission = {{ texture = \"mesh_attribute\", name = \"vertex_color\", scale = 3 }}\n\
         [[rectangles]]\nmaterial = \"floor\"\ntransform = {{ scale = 3, rotate = {{ axis = [1, 0, 0], angle = -90 }} }}\n\
         [[meshes]]\nfile = \"{}\"\nmaterial = \"lamp\"\n\
         transform = {{ scale = [0.9, 0.5, 0.5], rotate = {{ axis = [1, 0, 0], angle = 60 }}, translate = [0, 0.3, -0.4] }}\n",
        grid.display()
    )
}

/// Mitsuba 3.9.1 cannot be the reference for a mesh attribute as an area light's radiance: its
/// area emitter evaluates the radiance of a point it samples on a SurfaceInteraction made from
/// the position sample (`SurfaceInteraction(const PositionSample3f &, ...)`: prim_index 0, no
/// shape), where a mesh attribute needs the triangle; its emitter sampling mis-evaluates it (the
/// fixture with such a light was 1.3% darker in Mitsuba than pathlab's `plain` and `best`, which
/// agree to 0.08%). So the two halves are tested against each other: `plain` sees the light
/// only where rays meet it (the hit's barycentrics), `nee` lights the floor only through points
/// it samples (the sampled point's barycentrics). z-test on 4x4 blocks, both with their
/// variance: at least 99.75% of channels pass at a Šidák-corrected level (false failure below
/// 0.01), and `nee` scaled by 1.05 is rejected.
#[test]
fn a_mesh_attribute_light_is_the_same_met_and_sampled() {
    use pathlab::stats::{sidak, z_test};
    let scene = Scene::parse(&attribute_light_scene(), "lamp.toml").unwrap();
    assert!(scene.materials.iter().any(|m| matches!(m.emission_texture, Some(Texture::MeshAttribute { .. }))));
    let hits = render(&scene, Method::from_name("plain").unwrap(), 32768, 4820);
    let sampled = render(&scene, Method::from_name("nee").unwrap(), 4096, 4821);
    let alpha = sidak(0.01, 2);
    let z = z_test(&hits.downsample(4), &sampled.downsample(4), alpha);
    println!("plain against nee: {:.4} of {} channels pass, max |z| {:.2}", z.pass_fraction, z.channels, z.max_abs_z);
    assert!(z.pass_fraction >= 0.9975, "met and sampled disagree: {:.4} pass, max |z| {:.2}", z.pass_fraction, z.max_abs_z);
    let mut scaled = sampled.clone();
    scaled.mean.iter_mut().flatten().for_each(|x| *x *= 1.05);
    scaled.variance.iter_mut().flatten().for_each(|x| *x *= 1.05 * 1.05);
    let power = z_test(&hits.downsample(4), &scaled.downsample(4), alpha);
    assert!(power.pass_fraction < 0.9975, "a 5% error passes: {:.4}", power.pass_fraction);
}

/// A PLY quad of two triangles with a face attribute `face_shade` of `value` (one channel) or
/// three (`rgb`), under a sphere light, as TOML whose material's `diffuse` is `diffuse`.
fn quad_scene(dir: &std::path::Path, diffuse: &str, face: &str) -> String {
    let ply = format!(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
         element face 2\nproperty list uchar int vertex_indices\n{face}end_header\n"
    );
    let rows = if face.contains("shade_2") { ["0.25 0.5 0.75", "0.25 0.5 0.75"] } else { ["0.375", "0.375"] };
    let ply = format!("{ply}-1 0 -1\n1 0 -1\n1 0 1\n-1 0 1\n3 0 2 1 {}\n3 0 3 2 {}\n", rows[0], rows[1]);
    std::fs::write(dir.join("quad.ply"), ply).unwrap();
    format!(
        "[camera]\nposition = [0, 2, 3]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 50\n\
         [render]\nwidth = 24\nheight = 18\nmax_depth = 2\n\
         [materials.quad]\ndiffuse = {diffuse}\n[materials.lamp]\ndiffuse = 0\nemission = 6\n\
         [[spheres]]\ncenter = [0.3, 1.2, 0.2]\nradius = 0.3\nmaterial = \"lamp\"\n\
         [[meshes]]\nfile = \"quad.ply\"\nmaterial = \"quad\"\n"
    )
}

#[test]
fn a_constant_face_attribute_renders_the_untextured_image() {
    let dir = tempfile::tempdir().unwrap();
    let one = "property float shade_0\n";
    let plain = Scene::parse(&quad_scene(dir.path(), "0.375", one), dir.path().join("plain.toml")).unwrap();
    let textured =
        Scene::parse(&quad_scene(dir.path(), "{ texture = \"mesh_attribute\", name = \"face_shade\" }", one), dir.path().join("textured.toml")).unwrap();
    assert_eq!(textured.meshes[0].attribute("face_shade").map(|a| a.channels), Some(1));
    assert_ne!(plain.content_hash(), textured.content_hash());
    for (k, method) in ["mis", "plain"].iter().enumerate() {
        let method = Method::from_name(method).unwrap();
        let (a, b) = (render(&plain, method, 16, 4810 + k as u32), render(&textured, method, 16, 4810 + k as u32));
        assert!(a.mean.iter().any(|p| p[0] > 0.0), "{}: the quad is lit", method.name());
        // b0 v + b1 v + b2 v rounds v by a few ulps at most; the paths are the same.
        for (p, q) in a.mean.iter().zip(&b.mean) {
            for c in 0..3 {
                assert!((p[c] - q[c]).abs() <= 1e-5 * p[c].abs().max(1e-3), "{}: {p:?} against {q:?}", method.name());
            }
        }
    }
}

#[test]
fn mesh_attributes_are_read_as_mitsuba_reads_them_and_bad_ones_refused() {
    let scene = Scene::load(fixture()).unwrap();
    // The fixture's three readings: a colour, a scaled colour, a blend weight read as a scalar.
    let textures: Vec<&Texture> = scene.materials.iter().flat_map(|m| m.textures()).collect();
    let attributes: Vec<(&str, f64, bool)> = textures
        .iter()
        .filter_map(|t| match t {
            Texture::MeshAttribute { name, scale, scalar } => Some((name.as_str(), *scale, *scalar)),
            _ => None,
        })
        .collect();
    assert_eq!(attributes, vec![("vertex_color", 1.0, false), ("face_color", 0.9, false), ("face_weight", 1.0, true)]);
    // r g b make vertex_color, color_0..2 face_color, weight_0 face_weight, with their values.
    let grid = &scene.meshes.iter().find(|m| m.source.ends_with("grid.ply")).unwrap();
    let names: Vec<(&str, usize)> = grid.attributes.iter().map(|a| (a.name.as_str(), a.channels)).collect();
    assert_eq!(names, vec![("vertex_color", 3), ("face_color", 3), ("face_weight", 1)]);
    assert_eq!(grid.attributes[1].values.len(), 72 * 3);

    let dir = tempfile::tempdir().unwrap();
    let refused = |text: String, field: &str, message: &str| match Scene::parse(&text, dir.path().join("c.toml")) {
        Err(SceneError::Invalid(d)) => assert!(d.iter().any(|d| d.field == field && d.message.contains(message)), "{text}: {d:?}"),
        other => panic!("{text}: accepted ({:?})", other.map(|s| s.materials.clone())),
    };
    let one = "property float shade_0\n";
    let three = "property float shade_0\nproperty float shade_1\nproperty float shade_2\n";
    // A mesh without the attribute: the error names what it has.
    refused(quad_scene(dir.path(), "{ texture = \"mesh_attribute\", name = \"vertex_color\" }", one), "meshes[0].material", "has no attribute \"vertex_color\" (it has face_shade (1 channel))");
    // Three channels read as one number (a blend weight): Mitsuba's eval_1 gives 0 there.
    let blend = quad_scene(dir.path(), "0.5", three).replace(
        "[materials.lamp]",
        "blend = \"other\"\nblend_weight = { texture = \"mesh_attribute\", name = \"face_shade\" }\n[materials.other]\ndiffuse = 0.2\n[materials.lamp]",
    );
    refused(blend, "meshes[0].material", "which its material reads as one number");
    // The name's prefix, the texture on a sphere, as an emission.
    refused(quad_scene(dir.path(), "{ texture = \"mesh_attribute\", name = \"shade\" }", one), "materials.quad.diffuse", "must start with \"vertex_\" or \"face_\"");
    let on_sphere = quad_scene(dir.path(), "{ texture = \"mesh_attribute\", name = \"face_shade\" }", one)
        .replace("[[meshes]]", "[[spheres]]\ncenter = [2, 0, 0]\nradius = 0.5\nmaterial = \"quad\"\n[[meshes]]");
    refused(on_sphere, "spheres[1].material", "which only a triangle mesh has, not a sphere");
    let emission = quad_scene(dir.path(), "0.5", one).replace("emission = 6", "emission = { texture = \"mesh_attribute\", name = \"face_shade\", scale = -1 }");
    refused(emission, "materials.lamp.emission", "`scale` of a mesh_attribute emission must be >= 0");

    // XML: the name's prefix is refused at its line and column, as Mitsuba refuses it.
    let xml = "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><film type=\"hdrfilm\"><integer name=\"width\" value=\"4\"/><integer name=\"height\" value=\"4\"/></film></sensor>\n\
               <shape type=\"rectangle\"><bsdf type=\"diffuse\"><texture name=\"reflectance\" type=\"mesh_attribute\">\n<string name=\"name\" value=\"color\"/></texture></bsdf></shape>\n</scene>\n";
    let e = load_xml(xml, "t.xml").unwrap_err().to_string();
    assert!(e.contains("t.xml:4:") && e.contains("must start with \"vertex_\" or \"face_\""), "{e}");

    // convert writes the texture as the TOML field, which reads back to the same scene.
    let (toml_text, _) = pathlab::scene::mitsuba::to_toml(&fixture(), &[], dir.path()).unwrap();
    assert!(toml_text.contains("texture = \"mesh_attribute\"") && toml_text.contains("name = \"face_weight\""), "{toml_text}");
    let path = dir.path().join("mesh_attributes.toml");
    std::fs::write(&path, &toml_text).unwrap();
    assert_eq!(Scene::load(&path).unwrap().content_hash(), scene.content_hash(), "the round trip keeps the scene");
}
