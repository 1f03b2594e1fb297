"""`render` is `pathlab render`: the same scene, method, seed and spp give the same image bit for
bit (TOML and Mitsuba XML scenes); `Renderer.add` in pieces equals one render; the header."""

import os
import subprocess
import sys

import numpy as np
import pytest

import pathlab
from conftest import CORNELL_XML, FIXTURES, STUDY


@pytest.mark.parametrize(
    "scene, method, spp, seed, size",
    [
        (STUDY, "mis", 16, 3, (64, 32)),
        (STUDY, "plain", 9, 0, (48, 24)),
        (CORNELL_XML, "best", 8, 1, (32, 32)),
        # Names beyond the presets: one parser for the CLI and Python (`Method::from_name`).
        (CORNELL_XML, "sobol/cosine/mis-balance+uniform+solid-angle", 4, 2, (16, 16)),
    ],
)
def test_render_equals_cli_exr_bit_for_bit(cli, tmp_path, scene, method, spp, seed, size):
    w, h = size
    exr = tmp_path / "cli.exr"
    cli("render", scene, "--method", method, "--spp", spp, "--seed", seed, "--width", w, "--height", h, "--variance", "-q", "-o", exr)
    theirs = pathlab.read_exr(exr)
    ours = pathlab.render(pathlab.load_scene(scene, width=w, height=h), method, spp=spp, seed=seed, variance=True)
    assert ours.image.dtype == np.float32 and ours.image.shape == (h, w, 3)
    assert np.array_equal(ours.image, theirs.image), "mean differs from the CLI's EXR"
    assert np.array_equal(ours.variance, theirs.variance), "variance differs from the CLI's EXR"
    assert ours.spp == theirs.spp == spp
    # The header: every field the CLI writes, with the same values (the timing aside).
    assert ours.metadata.keys() == theirs.metadata.keys()
    for key in ours.metadata.keys() - {"render_seconds"}:
        assert ours.metadata[key] == theirs.metadata[key], key
    assert ours.rays == int(theirs.metadata["rays"])


def test_renderer_add_in_pieces_equals_one_render():
    scene = pathlab.load_scene(STUDY, width=40, height=20)
    one = pathlab.render(scene, "mis", spp=23, seed=5, variance=True)
    r = pathlab.Renderer(scene, "mis", seed=5)
    images = []
    for n in (1, 4, 18):
        r.add(n)
        images.append(r.image.copy())
    assert r.spp == 23
    assert np.array_equal(r.image, one.image)
    assert np.array_equal(r.variance, one.variance)
    assert r.render().metadata["spp"] == "23"
    # Every snapshot was a render of its own spp: the first equals a 1-spp render.
    assert np.array_equal(images[0], pathlab.render(scene, "mis", spp=1, seed=5).image)


def test_scene_properties_and_with():
    scene = pathlab.load_scene(STUDY)
    assert scene.size == (1024, 512) and scene.max_depth == 2 and scene.rr_depth is None
    assert [l["kind"] for l in scene.lights] == ["sphere", "sphere"]
    small = scene.with_(width=64, height=32, max_depth=3, rr_depth=2)
    assert small.size == (64, 32) and small.max_depth == 3 and small.rr_depth == 2
    assert scene.size == (1024, 512), "with_ returns a copy"
    assert small.with_(rr_depth=None).rr_depth is None
    # Another aspect ratio changes the framing, and says how (the study scene keeps fov_x).
    with pytest.warns(UserWarning, match="16x16 has another aspect ratio than the scene's 1024x512.*fov_x"):
        assert scene.with_(width=16, height=16).size == (16, 16)
    cornell = pathlab.load_scene(CORNELL_XML, defines={"spp": 16})
    assert cornell.spp == 16 and cornell.lights[0]["kind"] == "mesh"
    assert "pathlab.Scene(" in repr(cornell)


def test_time_budget_and_target():
    scene = pathlab.load_scene(STUDY, width=32, height=16)
    timed = pathlab.render(scene, "mis", time=0.3)
    assert timed.spp > 0 and 0.2 < timed.seconds < 5
    target = pathlab.render(scene, "mis", target_rel_error=0.05, spp=4096)
    assert target.error_estimate is not None
    est = target.error_estimate
    assert est["reached"] == (est["rel_mse"] <= 0.05)
    assert target.metadata["target_rel_mse"] == "0.05"


def test_write_and_read_exr_round_trip(cli, tmp_path):
    scene = pathlab.load_scene(STUDY, width=32, height=16)
    r = pathlab.render(scene, "nee", spp=8, variance=True)
    path = tmp_path / "r.exr"
    pathlab.write_exr(path, r)
    back = pathlab.read_exr(path)
    assert np.array_equal(back.image, r.image) and np.array_equal(back.variance, r.variance)
    assert back.metadata == r.metadata and back.spp == 8
    # The CLI reads what Python wrote (and scores it against itself perfectly).
    out = cli("compare", path, path, "--json").stdout
    assert '"rel_mse": 0.0' in out


def test_adapters_and_device():
    listed = pathlab.adapters()
    assert listed and all("name" in a for a in listed)
    assert pathlab.device()["name"] in [a["name"] for a in listed]


def test_a_render_on_a_headless_machine_prints_nothing(tmp_path):
    """Without XDG_RUNTIME_DIR (a server, a container, CI) Mesa's device-select layer would
    print "error: XDG_RUNTIME_DIR is invalid or not set" twice at the first render; the library
    switches the layer off for every front-end, as the CLI does."""
    env = {k: v for k, v in os.environ.items() if k not in ("XDG_RUNTIME_DIR", "NODEVICE_SELECT")}
    code = f"import pathlab; pathlab.render(pathlab.load_scene({str(STUDY)!r}, width=8, height=4), 'plain', spp=1)"
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert p.stderr == "", p.stderr


def test_delta_lights_are_listed_and_methods_blind_to_them_refused():
    # Mitsuba's point, spot and directional lights (tests/fixtures/delta_lights): only next
    # event estimation finds them, so a method without it is refused, naming the light.
    scene = pathlab.load_scene(STUDY.parents[2] / "tests" / "fixtures" / "delta_lights" / "delta_lights.xml", width=16, height=12)
    kinds = [l["kind"] for l in scene.lights]
    assert kinds == ["point", "spot", "directional"]
    spot = scene.lights[1]
    assert (spot["cutoff_angle"], spot["beam_width"]) == (30.0, 15.0) and spot["power"] > 0
    with pytest.raises(pathlab.RenderError, match="cannot see point light 0"):
        pathlab.render(scene, "plain", spp=1)
    image = pathlab.render(scene, "mis", spp=2, seed=1).image
    assert np.isfinite(image).all() and image.mean() > 0


def test_the_default_method_is_the_clis(cli, tmp_path):
    """Without a method, `render` uses the CLI's default: `best+env` under an environment map
    (as Mitsuba samples its envmap), `best` otherwise, and gives the CLI's image bit for bit."""
    for scene, expected, (w, h) in [(FIXTURES / "envmap" / "envmap.xml", "best+env", (8, 8)), (STUDY, "best", (8, 4))]:
        exr = tmp_path / "cli.exr"
        cli("render", scene, "--spp", 4, "--width", w, "--height", h, "-q", "-o", exr)
        theirs = pathlab.read_exr(exr)
        ours = pathlab.render(pathlab.load_scene(scene, width=w, height=h), spp=4)
        assert ours.metadata["method"] == theirs.metadata["method"] == expected
        assert np.array_equal(ours.image, theirs.image)


def test_textured_lights_are_listed_with_their_mean_and_render():
    # Mitsuba's area emitter with a textured radiance (tests/fixtures/textured_lights): a 4 x 3
    # EXR whose pixel means are (4.5, 3.375, 4.625), and a checkerboard.
    scene = pathlab.load_scene(FIXTURES / "textured_lights" / "textured_lights.xml", width=8, height=6)
    meshes = [l for l in scene.lights if l["kind"] == "mesh" and l["textured"]]
    assert len(meshes) == 2
    assert any(np.allclose(l["emission"], [4.5, 3.375, 4.625]) for l in meshes)
    image = pathlab.render(scene, "mis", spp=2, seed=1).image
    assert np.isfinite(image).all() and image.mean() > 0


def assert_mean_agrees_with_mitsuba(ours, fixture):
    """The image mean per channel of a render (with its variance) against Mitsuba 3.9.1's
    reference of tests/fixtures/FIXTURE (65536 spp, with its variance): a z-test of the mean
    with both variances; |z| < 4.5 on each of 3 channels fails falsely with probability below
    3 x 7e-6."""
    ref = pathlab.read_exr(FIXTURES / fixture / "reference.exr").image
    ref_var = pathlab.read_exr(FIXTURES / fixture / "reference_var.exr").image
    n = ours.image.shape[0] * ours.image.shape[1]
    for c in range(3):
        se = np.sqrt((ours.variance[..., c].sum() + ref_var[..., c].sum()) / n**2)
        z = (ours.image[..., c].mean() - ref[..., c].mean()) / se
        assert abs(z) < 4.5, f"{fixture}, channel {c}: z = {z:.2f}"


def test_mesh_attributes_render_as_mitsuba_renders_them():
    # Mitsuba's mesh_attribute texture (tests/fixtures/mesh_attributes: vertex colours, face
    # colours and a blend by a face weight on a PLY grid), through the Python API, against
    # Mitsuba's reference (assert_mean_agrees_with_mitsuba).
    scene = pathlab.load_scene(FIXTURES / "mesh_attributes" / "mesh_attributes.xml")
    assert (scene.width, scene.height) == (64, 48) and scene.num_triangles == 220
    assert_mean_agrees_with_mitsuba(pathlab.render(scene, "mis", spp=256, seed=4830, variance=True), "mesh_attributes")


def test_media_are_listed_and_render_as_mitsuba_renders_them():
    # Homogeneous participating media (tests/fixtures/media: a Henyey-Greenstein medium behind a
    # null sphere, an isotropic one behind a thin dielectric, a masked panel, under Mitsuba's
    # volpath), through the Python API: the media as listed, and the image against Mitsuba's
    # reference (assert_mean_agrees_with_mitsuba).
    scene = pathlab.load_scene(FIXTURES / "media" / "media.xml")
    media = {m["name"]: m for m in scene.media}
    assert set(media) == {"fog", "shape2-interior"}
    assert media["fog"]["phase"] == "hg" and media["fog"]["g"] == 0.6
    assert np.allclose(media["fog"]["sigma_t"], [2.4, 1.2, 0.6]) and not media["fog"]["camera"]
    assert media["shape2-interior"]["phase"] == "isotropic" and len(media["shape2-interior"]["bounded_by"]) == 1
    assert_mean_agrees_with_mitsuba(pathlab.render(scene, "mis", spp=256, seed=4930, variance=True), "media")


def test_heterogeneous_media_are_listed_and_render_as_mitsuba_renders_them():
    # Heterogeneous media and grid albedos (tests/fixtures/hetero_media: a grid extinction with a
    # grid albedo, a homogeneous medium with a grid albedo, a constant extinction in a box) under
    # Mitsuba's volpath, through the Python API: the media as listed, and the image against
    # Mitsuba's fixture.
    scene = pathlab.load_scene(FIXTURES / "hetero_media" / "hetero.xml")
    media = {m["name"]: m for m in scene.media}
    assert media["cloud"]["type"] == "heterogeneous" and media["cloud"]["scale"] == 3.0
    assert media["cloud"]["sigma_t"].endswith("rgb.vol") and media["cloud"]["albedo"].endswith("grey.vol")
    assert media["shape2-interior"]["type"] == "homogeneous" and np.allclose(media["shape2-interior"]["sigma_t"], [2.0, 2.0, 2.0])
    assert np.allclose(media["shape3-interior"]["sigma_t"], [3.0, 2.0, 1.0]) and np.allclose(media["shape3-interior"]["albedo"], 0.75)
    assert_mean_agrees_with_mitsuba(pathlab.render(scene, "mis", spp=256, seed=5130, variance=True), "hetero_media")


def test_disk_lights_are_listed_with_their_area_and_power():
    # Mitsuba's disk as an area light (tests/fixtures/quadrics): the overhead disk is the unit
    # disk scaled by 0.7 x 0.35, so its area is pi 0.245; power is pi x area x luminance.
    scene = pathlab.load_scene(FIXTURES / "quadrics" / "quadrics.xml", width=8, height=8)
    disks = [l for l in scene.lights if l["kind"] == "disk"]
    assert len(disks) == 2
    overhead = disks[0]
    assert abs(overhead["area"] - np.pi * 0.7 * 0.35) < 1e-9
    luminance = 0.212671 * 8 + 0.715160 * 7 + 0.072169 * 6
    assert abs(overhead["power"] - np.pi * overhead["area"] * luminance) < 1e-6 * overhead["power"]
    assert overhead["normal"][1] < -0.9 and not overhead["two_sided"]
    image = pathlab.render(scene, "mis", spp=2, seed=1).image
    assert np.isfinite(image).all() and image.mean() > 0
