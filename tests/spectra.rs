//! Spectra in Mitsuba XML become the colours Mitsuba 3.9.1's RGB variants give them, role by
//! role: a reflectance (D65-weighted, clamped to [0, 1]), an unbounded conductor index
//! (D65-weighted, clamped at 0) and an emission (unweighted; a uniform spectrum is the sRGB
//! colour of XYZ = (1, 1, 1)), against Mitsuba's own numbers (`scripts/spectra.py`,
//! `tests/fixtures/spectra/mitsuba.json`). A blackbody gets the colour Mitsuba's spectral
//! variant integrates. Deterministic: no sampling.

use std::path::Path;

use pathlab::scene::spectrum::{Spectrum, SpectrumRole};
use pathlab::scene::{Bsdf, Scene, SceneError, Severity};

fn fixture() -> serde_json::Value {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/spectra/mitsuba.json");
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Mitsuba stores each colour as f32: agreement to a few f32 ulps (and 1e-6 near zero).
fn close(ours: [f64; 3], theirs: [f64; 3], rel: f64) -> bool {
    (0..3).all(|c| (ours[c] - theirs[c]).abs() <= rel * theirs[c].abs() + 1e-6)
}

fn rgb(v: &serde_json::Value) -> [f64; 3] {
    let a = v.as_array().unwrap();
    [0, 1, 2].map(|c| a[c].as_f64().unwrap())
}

#[test]
fn spectra_become_the_colours_mitsuba_gives_them_in_each_role() {
    let f = fixture();
    let conversions = f["conversions"].as_array().unwrap();
    assert_eq!(conversions.len(), 18, "6 spectra x 3 roles");
    for c in conversions {
        let role = match c["role"].as_str().unwrap() {
            "reflectance" => SpectrumRole::Reflectance,
            "emission" => SpectrumRole::Emission,
            "unbounded" => SpectrumRole::Unbounded,
            other => panic!("role {other}"),
        };
        let spectrum = Spectrum::parse(c["value"].as_str().unwrap()).unwrap();
        let ours = spectrum.to_srgb(role).rgb;
        let theirs = rgb(&c["rgb"]);
        assert!(close(ours, theirs, 2e-6), "{} as {role:?}: pathlab {ours:?}, Mitsuba {theirs:?}", c["spectrum"]);
    }
    // A blackbody, as Mitsuba's spectral variant integrates Planck's law (its f32 evaluation).
    for b in f["blackbody"].as_array().unwrap() {
        let t = b["temperature"].as_f64().unwrap();
        let ours = Spectrum::Blackbody { temperature: t, min: 360.0, max: 830.0 }.to_srgb(SpectrumRole::Emission).rgb;
        let theirs = rgb(&b["rgb"]);
        assert!(close(ours, theirs, 2e-5), "blackbody at {t} K: pathlab {ours:?}, Mitsuba {theirs:?}");
    }
}

fn write(dir: &Path, text: &str) -> std::path::PathBuf {
    let path = dir.join("s.xml");
    std::fs::write(&path, text).unwrap();
    path
}

fn scene(body: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/><rfilter type="box"/></film>
    </sensor>
{body}
</scene>
"#
    )
}

const COARSE: &str = "400:0.1, 500:0.5, 600:0.9, 700:0.3";

#[test]
fn spectra_in_xml_are_read_by_the_role_of_their_parameter() {
    let dir = tempfile::tempdir().unwrap();
    let body = format!(
        r#"    <shape type="rectangle">
        <bsdf type="diffuse"><spectrum name="reflectance" value="{COARSE}"/></bsdf>
        <emitter type="area"><spectrum name="radiance" value="2"/></emitter>
    </shape>
    <shape type="cube">
        <bsdf type="conductor"><spectrum name="eta" value="400:0, 500:8, 600:15.6, 700:18.4"/><spectrum name="k" value="{COARSE}"/></bsdf>
    </shape>
    <shape type="sphere">
        <bsdf type="diffuse"><spectrum name="reflectance" value="400:0, 500:8, 600:15.6, 700:18.4"/></bsdf>
        <emitter type="area"><spectrum type="blackbody" name="radiance"><float name="temperature" value="2700"/></spectrum></emitter>
    </shape>"#
    );
    let s = Scene::load(write(dir.path(), &scene(&body))).unwrap();
    let coarse = Spectrum::parse(COARSE).unwrap();
    let light = Spectrum::parse("400:0, 500:8, 600:15.6, 700:18.4").unwrap();
    let phong = |i: usize| match &s.materials[i].bsdf {
        Bsdf::Phong(p) => p.diffuse.to_array(),
        other => panic!("{other:?}"),
    };
    assert_eq!(phong(0), coarse.to_srgb(SpectrumRole::Reflectance).rgb);
    assert_eq!(s.materials[0].emission.to_array(), Spectrum::Uniform(2.0).to_srgb(SpectrumRole::Emission).rgb);
    // A uniform emission is not grey in Mitsuba's RGB variants: 2 x sRGB(XYZ = 1).
    assert!(s.materials[0].emission.x > 2.3 && s.materials[0].emission.z < 1.9, "{:?}", s.materials[0].emission);
    let Bsdf::Conductor(c) = &s.materials[1].bsdf else { panic!("{:?}", s.materials[1].bsdf) };
    assert_eq!(c.eta.to_array(), light.to_srgb(SpectrumRole::Unbounded).rgb);
    assert_eq!(c.k.to_array(), coarse.to_srgb(SpectrumRole::Unbounded).rgb);
    assert!(c.eta.x > 1.0, "an unbounded index is not clamped to 1: {:?}", c.eta);
    // A reflectance above 1 is clamped, as Mitsuba clamps it, with its warning.
    assert_eq!(phong(2), [1.0; 3]);
    assert!(s.warnings.iter().any(|w| w.message.contains("clamped to") && w.line > 0), "{:?}", s.warnings);
    assert_eq!(s.materials[2].emission.to_array(), Spectrum::Blackbody { temperature: 2700.0, min: 360.0, max: 830.0 }.to_srgb(SpectrumRole::Emission).rgb);
}

#[test]
fn a_spectral_data_file_is_the_same_spectrum_as_its_pairs() {
    // Mitsuba's .spd: a wavelength and a value per line, `#` comments, blank lines; found by the
    // resolver in a <path> folder. It gives exactly the colour of the same pairs in `value`.
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("spectra")).unwrap();
    std::fs::write(dir.path().join("spectra/paint.spd"), "# wavelength (nm)  reflectance\n400 0.10\n\n500 0.55   # green\n600 0.30\r\n700 0.80\n").unwrap();
    let body = r#"<path value="spectra"/>
        <bsdf type="diffuse" id="file"><spectrum name="reflectance" filename="paint.spd"/></bsdf>
        <bsdf type="diffuse" id="pairs"><spectrum name="reflectance" value="400:0.10, 500:0.55, 600:0.30, 700:0.80"/></bsdf>
        <shape type="cube"><ref id="file"/></shape>
        <shape type="sphere"><point name="center" x="3" y="0" z="0"/><ref id="pairs"/></shape>"#;
    let s = Scene::load(write(dir.path(), &scene(body))).unwrap();
    let colour = |name: &str| match &s.materials.iter().find(|m| m.name == name).unwrap_or_else(|| panic!("{name}")).bsdf {
        Bsdf::Phong(p) => p.diffuse.to_array(),
        other => panic!("{other:?}"),
    };
    let expected = Spectrum::parse("400:0.10, 500:0.55, 600:0.30, 700:0.80").unwrap().to_srgb(SpectrumRole::Reflectance).rgb;
    assert_eq!(colour("file"), expected);
    assert_eq!(colour("pairs"), expected);
}

#[test]
fn bad_spectra_are_refused_with_line_and_column() {
    let cases = [
        (r#"<bsdf type="diffuse" id="d"><spectrum name="reflectance" value="500:0.1, 400:0.2"/></bsdf>"#, "500:0.1", "wavelengths must increase"),
        (r#"<bsdf type="diffuse" id="d"><spectrum name="reflectance" value="400:0.1"/></bsdf>"#, "400:0.1", "at least two"),
        (r#"<bsdf type="diffuse" id="d"><spectrum name="reflectance" value="400:x, 500:1"/></bsdf>"#, "400:x", "is not a number or a wavelength:value pair"),
        (r#"<bsdf type="diffuse" id="d"><spectrum name="reflectance" filename="missing.spd"/></bsdf>"#, "<spectrum name", "spectral data file \"missing.spd\" not found (searched"),
        (r#"<bsdf type="diffuse" id="d"><spectrum name="reflectance" filename="bad.spd"/></bsdf>"#, "<spectrum name", "bad.spd:3: expected a wavelength and a value, got `500 0.5 7`"),
        (r#"<bsdf type="diffuse" id="d"><spectrum name="reflectance" filename="down.spd"/></bsdf>"#, "<spectrum name", "wavelengths must increase"),
        (r#"<bsdf type="diffuse" id="d"><spectrum name="reflectance" filename="a.txt"/></bsdf>"#, "<spectrum name", "ending in .spd only"),
        (r#"<bsdf type="diffuse" id="d"><spectrum name="reflectance" type="d65"/></bsdf>"#, "<spectrum name", "<spectrum type=\"d65\"> is not supported"),
        (r#"<bsdf type="diffuse" id="d"><spectrum name="reflectance" type="blackbody"><float name="temperature" value="3000"/></spectrum></bsdf>"#, "<spectrum name", "a blackbody is an emission spectrum"),
        (r#"<shape type="cube"><emitter type="area"><spectrum name="radiance" type="blackbody"><float name="temperature" value="-3"/></spectrum></emitter></shape>"#, "-3", "finite number of kelvin > 0"),
        (r#"<shape type="cube"><emitter type="area"><spectrum name="radiance" type="blackbody"/></emitter></shape>"#, "<spectrum name", "needs <float name=\"temperature\">"),
    ];
    for (body, at, message) in cases {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("bad.spd"), "# a comment\n400 0.1\n500 0.5 7\n").unwrap();
        std::fs::write(dir.path().join("down.spd"), "500 0.1\n400 0.5\n").unwrap();
        std::fs::write(dir.path().join("a.txt"), "400 0.1\n500 0.5\n").unwrap();
        let text = scene(body);
        let path = write(dir.path(), &text);
        let d = match Scene::load(&path) {
            Err(SceneError::Invalid(d)) => d.into_iter().find(|d| d.severity == Severity::Error).unwrap(),
            other => panic!("{body}: not refused: {:?}", other.map(|s| s.materials.len())),
        };
        assert!(d.message.contains(message), "expected `{message}`: {d}");
        let offset = text.find(at).unwrap();
        let line = text[..offset].matches('\n').count() + 1;
        let column = offset - text[..offset].rfind('\n').map_or(0, |i| i + 1) + 1;
        assert_eq!((d.file.as_path(), d.line, d.column), (path.as_path(), line, column), "{d}");
    }
}
