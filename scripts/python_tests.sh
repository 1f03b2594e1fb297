#!/usr/bin/env bash
# The Python package's tests: a venv (target/python-venv, made once), the package installed
# into it with `pip install ./python` (the extension builds into the shared target/ directory),
# then pytest on python/tests from a directory outside the repository, so that the installed
# package, not the source folder, is what the tests import.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
venv="${PATHLAB_VENV:-$repo/target/python-venv}"
python="${PYTHON:-python3}"

if ! "$python" -c 'import ensurepip, venv' 2>/dev/null; then
    echo "NOT RUN: python tests: $python cannot make a venv (Debian/Ubuntu: apt-get install python3-venv)" >&2
    exit 1
fi
# The CLI the tests compare against (already built by `cargo test --release`).
cargo build --release --quiet --bin pathlab --manifest-path "$repo/Cargo.toml"

start=$SECONDS
[ -x "$venv/bin/python" ] || "$python" -m venv "$venv"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check --upgrade pip
"$venv/bin/pip" install --quiet --disable-pip-version-check pytest scikit-image tqdm numpy mypy
echo "python tests: test dependencies ready in $((SECONDS - start)) s"
start=$SECONDS
# With the extension's `viewer` feature (never called from Python), the build resolves every crate
# it shares with `cargo test`'s to the same features and reuses them: pyo3, numpy and the
# extension compile, not the library again (python/Cargo.toml, tests/build_features.rs).
MATURIN_PEP517_ARGS="--features viewer" \
    "$venv/bin/pip" install --quiet --disable-pip-version-check --force-reinstall --no-deps "$repo/python"
echo "python tests: pip install ./python took $((SECONDS - start)) s"

scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
cd "$scratch"
PATHLAB_CLI="$repo/target/release/pathlab" "$venv/bin/python" -m pytest -p no:cacheprovider -v "$repo/python/tests" "$@"
