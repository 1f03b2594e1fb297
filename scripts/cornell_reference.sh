#!/usr/bin/env bash
# Reference render of the Cornell box fixture, tests/fixtures/cornell/, by the reference renderer
# (Mitsuba 3, llvm_ad_rgb) loading assets/scenes/cornell_box.xml itself, the file pathlab reads
# (scripts/xml_reference.py: Mitsuba's -D for the size; the file's box filter, independent
# sampler and path integrator with max_depth 8 and Mitsuba's default Russian roulette from
# depth 5). The file is mi.cornell_box() (mitsuba3 src/python/python/util.py) written out, with a
# box filter instead of its gaussian; MAX_DEPTH overrides its depth. It renders PASSES passes
# (default 64) of SPP samples per pixel each (default 1024) at WIDTH x HEIGHT (default 64x64)
# with seeds SEED, SEED+1, ... (default 0) and writes:
#   reference.exr      mean image: linear float32 RGB, channels R, G, B
#   reference_var.exr  per-pixel, per-channel variance of that mean (sample variance of the pass
#                      images / PASSES), same layout; needs PASSES >= 2
#   reference.png      sRGB-encoded, clipped 8-bit preview of the mean
#   reference.json     run record (mitsuba_version, size, spp, passes, seeds, timing, mean_rgb)
# into OUT (default tests/fixtures/cornell). The render takes long at the defaults (see the
# timing in reference.json: render_s, samples_per_s); compute it once and commit the outputs.
#
# Set-up of the reference renderer (once per machine), from ../shared/reference-renderer/README.md:
#   apt-get install -y libllvm19
#   python3 -m venv /tmp/mitsuba-venv && /tmp/mitsuba-venv/bin/pip install -r ../shared/reference-renderer/requirements.txt
#
# Usage: [WIDTH=w HEIGHT=h SPP=n PASSES=p SEED=s MAX_DEPTH=d OUT=dir] scripts/cornell_reference.sh
#   e.g. a quick check: WIDTH=8 HEIGHT=8 SPP=16 PASSES=2 OUT=/tmp/cbtest scripts/cornell_reference.sh
set -euo pipefail
cd "$(dirname "$0")/.."
py=${MITSUBA_PYTHON:-/tmp/mitsuba-venv/bin/python}
w=${WIDTH:-64}; h=${HEIGHT:-64}; spp=${SPP:-1024}; passes=${PASSES:-64}; seed=${SEED:-0}
out=${OUT:-tests/fixtures/cornell}
[ -x "$py" ] || { echo "no Mitsuba python at $py (see the set-up above)" >&2; exit 1; }
[ "$passes" -ge 2 ] || { echo "PASSES must be >= 2 for the variance of the mean" >&2; exit 1; }
mkdir -p "$out"
depth=()
[ -n "${MAX_DEPTH:-}" ] && depth=(-D "max_depth=$MAX_DEPTH")
"$py" scripts/xml_reference.py assets/scenes/cornell_box.xml -D "resx=$w" -D "resy=$h" "${depth[@]}" \
    --spp "$spp" --passes "$passes" --seed "$seed" \
    --out "$out/reference.exr" --var-out "$out/reference_var.exr" --png "$out/reference.png" \
    --json-out "$out/reference.json"
