#!/usr/bin/env bash
# Reference render of a Mitsuba XML fixture of the suite by the reference renderer (Mitsuba
# 3.9.1, llvm_ad_rgb) loading the file itself (scripts/xml_reference.py; Mitsuba's -D resx/resy
# for the size; the file's own filter, sampler and integrator): PASSES passes (default 64) of SPP
# samples per pixel (default 1024) at WIDTH x HEIGHT (default 48x48), seeds SEED, SEED+1, ...
# (default 0), written as reference.exr, reference_var.exr (variance of the mean),
# reference.png and reference.json beside the file. Set-up of the reference renderer: see
# scripts/cornell_reference.sh.
#
# Usage: [WIDTH=w HEIGHT=h SPP=n PASSES=p SEED=s] scripts/xml_fixture_reference.sh tests/fixtures/DIR/FILE.xml
set -euo pipefail
cd "$(dirname "$0")/.."
xml=${1:?usage: scripts/xml_fixture_reference.sh tests/fixtures/DIR/FILE.xml}
py=${MITSUBA_PYTHON:-/tmp/mitsuba-venv/bin/python}
w=${WIDTH:-48}; h=${HEIGHT:-48}; spp=${SPP:-1024}; passes=${PASSES:-64}; seed=${SEED:-0}
out=$(dirname "$xml")
[ -x "$py" ] || { echo "no Mitsuba python at $py (see scripts/cornell_reference.sh)" >&2; exit 1; }
[ "$passes" -ge 2 ] || { echo "PASSES must be >= 2 for the variance of the mean" >&2; exit 1; }
"$py" scripts/xml_reference.py "$xml" -D "resx=$w" -D "resy=$h" \
    --spp "$spp" --passes "$passes" --seed "$seed" \
    --out "$out/reference.exr" --var-out "$out/reference_var.exr" --png "$out/reference.png" \
    --json-out "$out/reference.json"
