"""Shared fixtures of the Python package's tests: the repository's scenes and fixtures, the
CLI binary to compare against, and a scratch directory outside the repository."""

import os
import subprocess
from pathlib import Path

import pytest

#: The repository: these tests run against the installed package, reading its assets from here.
REPO = Path(__file__).resolve().parents[2]
STUDY = REPO / "assets" / "scenes" / "study.toml"
CORNELL_XML = REPO / "assets" / "scenes" / "cornell_box.xml"
FIXTURES = REPO / "tests" / "fixtures"


def cli_path() -> Path:
    return Path(os.environ.get("PATHLAB_CLI", REPO / "target" / "release" / "pathlab"))


@pytest.fixture(scope="session")
def cli():
    """Runs the `pathlab` binary; a missing binary fails the test, saying how to build it."""
    path = cli_path()
    if not path.exists():
        pytest.fail(f"{path} is missing: build it with `cargo build --release` (or set PATHLAB_CLI)")

    def run(*args, check=True):
        p = subprocess.run([str(path), *map(str, args)], capture_output=True, text=True)
        if check and p.returncode != 0:
            raise AssertionError(f"pathlab {' '.join(map(str, args))} exited {p.returncode}:\n{p.stderr}")
        return p

    return run
