"""`study` and `advise` from Python: the parsed results.json with every method; the advice
table."""

import json

import pytest

import pathlab
from conftest import STUDY

METHODS = ["plain", "halton", "cosine", "phong", "nee", "mis", "best"]


def test_quick_study_returns_every_method(tmp_path):
    scene = pathlab.load_scene(STUDY)
    # The library's warnings arrive as Python warnings: at 48x24 the quick study's reference is
    # too noisy for its best runs' errors, and says so.
    with pytest.warns(UserWarning, match="render a longer reference"):
        results = pathlab.study(scene, tmp_path / "study", quick=True, size=(48, 24), spp=[1, 4, 16], time=[0.05], seeds=1)
    assert results == json.loads((tmp_path / "study" / "results.json").read_text())
    # Every method in every table: the equal-sample rows at each budget, the equal-time rows,
    # a convergence fit and a bias verdict.
    for table in ("equal_samples", "equal_time", "convergence", "verdicts"):
        assert sorted({row["method"] for row in results[table]}) == sorted(METHODS), table
    assert sorted(row["budget"] for row in results["equal_samples"] if row["method"] == "mis") == [1, 4, 16]
    assert (results["width"], results["height"]) == (48, 24)
    assert (tmp_path / "study" / "report.md").exists()


def test_advise_returns_its_table():
    scene = pathlab.load_scene(STUDY, width=32, height=16)
    table = pathlab.advise(scene, target_rel_error=0.01, methods=["plain", "mis"], pilot_seconds=0.3)
    assert sorted(row["method"] for row in table) == ["mis", "plain"]
    assert all(row["pilot_spp"] >= 1 and "predicted_seconds" in row for row in table)
