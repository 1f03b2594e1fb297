"""Editors complete the package: the native module's stub names everything the extension
defines (and nothing it does not), and the installed package type-checks under mypy --strict."""

import ast
import subprocess
import sys
from pathlib import Path

import pathlab
from pathlab import _pathlab


def test_stub_matches_the_extension():
    stub = Path(_pathlab.__file__).with_name("_pathlab.pyi")
    assert stub.exists(), "the wheel carries _pathlab.pyi"
    tree = ast.parse(stub.read_text())
    stubbed = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            stubbed.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            stubbed.add(node.target.id)
    native = {n for n in dir(_pathlab) if not n.startswith("_")}
    assert native == stubbed - {n for n in stubbed if n.startswith("_")}
    assert Path(pathlab.__file__).with_name("py.typed").exists()


def test_package_type_checks_strictly(tmp_path):
    p = subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-incremental", "-p", "pathlab"], capture_output=True, text=True, cwd=tmp_path
    )
    assert p.returncode == 0, p.stdout + p.stderr
