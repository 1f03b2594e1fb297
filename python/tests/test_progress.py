"""Progress: a tqdm bar with progress=True, and nothing at all printed otherwise."""

import pathlab
from conftest import STUDY


def test_silent_by_default(capfd):
    pathlab.render(pathlab.load_scene(STUDY, width=32, height=16), "mis", spp=64)
    out, err = capfd.readouterr()
    assert out == "" and err == ""


def test_tqdm_bar_when_asked(capfd):
    pathlab.render(pathlab.load_scene(STUDY, width=128, height=64), "best", spp=2048, progress=True)
    out, err = capfd.readouterr()
    assert "spp" in err and "render best" in err, err
