"""A researcher's own technique from Python: `pathlab.Technique` loaded with a scene renders
(its header naming the file's SHA-256) and joins a study; one the check refuses raises
`RenderError` with the check's report before anything renders."""

import hashlib
import warnings

import pytest

import pathlab
from conftest import REPO, STUDY

EXAMPLES = REPO / "examples" / "techniques"


def test_a_technique_round_trips_into_render_and_study(tmp_path):
    t = pathlab.Technique(f"light:{EXAMPLES / 'sphere_area.wgsl'}")
    assert (t.kind, t.name, t.method()) == ("light", "sphere_area", "mis+light=sphere_area")
    scene = pathlab.load_scene(STUDY, width=32, height=16, techniques=[t])
    sha = hashlib.sha256((EXAMPLES / "sphere_area.wgsl").read_bytes()).hexdigest()
    assert scene.techniques == [("light", "sphere_area", str(EXAMPLES / "sphere_area.wgsl"), sha)]
    r = pathlab.render(scene, t.method(), spp=16, seed=2)
    assert r.method == "mis+light=sphere_area"
    assert r.metadata["techniques"] == f"light=sphere_area@{sha}"
    assert r.metadata["technique_faults"] == "0"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        results = pathlab.study(scene, tmp_path / "study", methods=["mis", t.method()], quick=True, size=(32, 16), spp=[1, 4], time=[0.05], seeds=1, reference_spp=256)
    assert sorted({row["method"] for row in results["equal_samples"]}) == ["mis", "mis+light=sphere_area"]


def test_a_refused_technique_raises_with_the_report():
    t = pathlab.Technique(EXAMPLES / "phong_n_plus_2.wgsl", kind="bsdf")
    scene = pathlab.load_scene(STUDY, width=16, height=8, techniques=[t])
    with pytest.raises(pathlab.RenderError, match=r"(?s)refused.*not 1 \(a wrongly normalised pdf\)"):
        pathlab.render(scene, t.method("phong"), spp=4)
    with pytest.raises(ValueError, match="KIND:FILE.wgsl"):
        pathlab.Technique("phong_lobe.wgsl")
    with pytest.raises(ValueError, match=r"syntax_error\.wgsl:6:5"):
        pathlab.load_scene(STUDY, techniques=[pathlab.Technique(REPO / "tests" / "fixtures" / "techniques" / "syntax_error.wgsl", kind="bsdf")])


def test_an_unproven_technique_renders_when_allowed_and_says_so():
    t = pathlab.Technique(EXAMPLES / "phong_n_plus_2.wgsl", kind="bsdf", allow_unproven=True)
    scene = pathlab.load_scene(STUDY, width=16, height=8, techniques=[t])
    r = pathlab.render(scene, t.method("phong"), spp=4)
    assert r.metadata["technique_verdict"].startswith("UNPROVEN: bsdf:phong_n_plus_2")
    progressive = pathlab.Renderer(scene, t.method("mis"))
    assert progressive.add(2).render().metadata["technique_verdict"].startswith("UNPROVEN")


def test_triangle_light_and_microfacet_techniques_are_proven_and_render():
    """The light kind's triangle functions on the Cornell box's light, and the bsdf kind's
    microfacet functions on the conductors: each proven, each recorded in the header."""
    root = REPO / "assets" / "scenes"
    for kind, file, scene_file in [("light", "triangle_area.wgsl", "cornell_box.toml"), ("bsdf", "ggx_spherical_caps.wgsl", "cornell_conductors.xml")]:
        t = pathlab.Technique(f"{kind}:{EXAMPLES / file}")
        scene = pathlab.load_scene(root / scene_file, width=16, height=16, techniques=[t])
        r = pathlab.render(scene, t.method(), spp=8, seed=3)
        assert r.method == f"mis+{kind}={t.name}"
        assert r.metadata["technique_verdict"] == "proven"
        assert r.metadata["technique_faults"] == "0"
