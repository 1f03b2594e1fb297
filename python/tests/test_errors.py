"""Bad input raises the Python error a user expects, naming what is wrong: `SceneError` (a
`ValueError`) with the CLI's own `file:line:column: error:` text, TypeError for a wrong type,
ValueError for an impossible value."""

import re

import numpy as np
import pytest

import pathlab
from conftest import STUDY


def test_bad_scene_raises_scene_error_with_the_cli_message(cli, tmp_path):
    bad = tmp_path / "bad.toml"
    text = STUDY.read_text().replace("max_depth   = 2", "max_depth   = 0", 1)
    assert text != STUDY.read_text()
    bad.write_text(text)
    with pytest.raises(pathlab.SceneError) as info:
        pathlab.load_scene(bad)
    assert isinstance(info.value, ValueError)
    message = str(info.value)
    assert re.match(rf"{re.escape(str(bad))}:\d+:\d+: error: ", message), message
    cli_stderr = cli("check", bad, check=False).stderr.strip()
    assert message == cli_stderr


def test_bad_xml_names_line_and_column(tmp_path):
    bad = tmp_path / "bad.xml"
    bad.write_text('<scene version="3.0.0">\n  <bsdf type="diffuse">\n    <rgb name="reflectance" value="0.5, x"/>\n  </bsdf>\n</scene>\n')
    with pytest.raises(pathlab.SceneError, match=rf"{re.escape(str(bad))}:3:\d+: error"):
        pathlab.load_scene(bad)


def test_missing_scene_file():
    with pytest.raises(pathlab.SceneError, match="cannot read scene file"):
        pathlab.load_scene("/nonexistent/scene.toml")


def small():
    return pathlab.load_scene(STUDY, width=16, height=8)


def test_unknown_method_and_strategy():
    with pytest.raises(ValueError, match="method: unknown method `nonsense` \\(known: plain, "):
        pathlab.render(small(), "nonsense", spp=1)
    with pytest.raises(ValueError, match="sampler: unknown sampler `lattice` \\(known: independent, "):
        pathlab.render(small(), "mis", spp=1, sampler="lattice")
    with pytest.raises(TypeError, match="method must be a str"):
        pathlab.render(small(), 3, spp=1)


def test_negative_or_wrong_spp():
    with pytest.raises(ValueError, match="spp must be at least 1, not -4"):
        pathlab.render(small(), "mis", spp=-4)
    with pytest.raises(ValueError, match="spp must be at least 1, not 0"):
        pathlab.Renderer(small(), "mis").add(0)
    with pytest.raises(TypeError, match="spp must be an int, not str"):
        pathlab.render(small(), "mis", spp="64")
    with pytest.raises(TypeError, match="spp must be an int, not float"):
        pathlab.render(small(), "mis", spp=2.5)
    with pytest.raises(ValueError, match="give spp or time, not both"):
        pathlab.render(small(), "mis", spp=4, time=1.0)
    with pytest.raises(ValueError, match="time must be a positive"):
        pathlab.render(small(), "mis", time=-1.0)


def test_scene_overrides_are_checked():
    with pytest.raises(ValueError, match="width must be at least 1, not 0"):
        pathlab.load_scene(STUDY, width=0)
    with pytest.raises(TypeError, match="max_depth must be an int, not str"):
        small().with_(max_depth="3")
    with pytest.raises(TypeError, match="unexpected keyword argument 'widht'"):
        pathlab.load_scene(STUDY, widht=10)
    with pytest.raises(ValueError, match="defines are \\$name values of a Mitsuba XML scene"):
        pathlab.load_scene(STUDY, defines={"spp": 4})


def test_compare_refuses_wrong_dtype_and_shape():
    a = np.zeros((8, 8, 3), np.float32)
    with pytest.raises(TypeError, match="test must be a float array .* not dtype int64"):
        pathlab.compare(np.zeros((8, 8, 3), np.int64), a)
    with pytest.raises(TypeError, match="reference must be a float array .* not dtype complex128"):
        pathlab.compare(a, np.zeros((8, 8, 3), complex))
    with pytest.raises(ValueError, match=r"test must have shape \(H, W, 3\), not \(8, 8\)"):
        pathlab.compare(np.zeros((8, 8), np.float32), a)
    with pytest.raises(ValueError, match=r"test must have shape \(H, W, 3\), not \(8, 8, 4\)"):
        pathlab.compare(np.zeros((8, 8, 4), np.float32), a)
    with pytest.raises(ValueError, match="the shapes differ"):
        pathlab.compare(np.zeros((8, 9, 3), np.float32), a)
    with pytest.raises(ValueError, match="non-finite"):
        pathlab.metrics.psnr(np.full((8, 8, 3), np.nan, np.float32), a)
    with pytest.raises(ValueError, match="display"):
        pathlab.compare(a, a, display="gamma:x")


def test_study_and_advise_refuse_bad_options(tmp_path):
    with pytest.raises(TypeError, match="unexpected keyword argument 'sppp'"):
        pathlab.study(small(), tmp_path, sppp=[1])
    with pytest.raises(TypeError, match="spp must be a list, not int"):
        pathlab.study(small(), tmp_path, spp=4)
    with pytest.raises(ValueError, match="give target_rel_error or target_psnr"):
        pathlab.advise(small())


def test_missing_vulkan_driver_says_how_to_install_one(tmp_path):
    # A process whose Vulkan loader finds no driver (pointed at a manifest that does not exist).
    import os
    import subprocess
    import sys

    env = dict(os.environ, VK_ICD_FILENAMES=str(tmp_path / "none.json"), VK_DRIVER_FILES=str(tmp_path / "none.json"))
    code = (
        "import pathlab\n"
        "try:\n    pathlab.device()\nexcept pathlab.GpuError as e:\n    print('GpuError:', e)\n"
        "else:\n    print('no error')\n"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith("GpuError: no Vulkan, Metal or DX12 adapter found"), p.stdout
    assert "apt-get install -y mesa-vulkan-drivers" in p.stdout
