#!/usr/bin/env bash
# Reference render of the Cornell box fixture, tests/fixtures/cornell/, with the reference renderer
# (Mitsuba 3, llvm_ad_rgb): Mitsuba's built-in mi.cornell_box() through mitsuba_ref.py, which
# overrides its gaussian pixel filter with a box filter (one sample, one pixel), uses the
# independent sampler and renders at WIDTH x HEIGHT (default 64x64); the integrator stays
# Mitsuba's `path` with the scene's max_depth 8 (Mitsuba's convention: 1 = visible emitters only)
# and default Russian roulette, unless MAX_DEPTH is set. It renders PASSES passes (default 64) of
# SPP samples per pixel each (default 1024) with seeds SEED, SEED+1, ... (default 0) and writes:
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
ref=${REFERENCE_RENDERER:-../shared/reference-renderer}
w=${WIDTH:-64}; h=${HEIGHT:-64}; spp=${SPP:-1024}; passes=${PASSES:-64}; seed=${SEED:-0}
out=${OUT:-tests/fixtures/cornell}
[ -x "$py" ] || { echo "no Mitsuba python at $py (see the set-up above)" >&2; exit 1; }
[ -f "$ref/mitsuba_ref.py" ] || { echo "no mitsuba_ref.py in $ref (set REFERENCE_RENDERER)" >&2; exit 1; }
[ "$passes" -ge 2 ] || { echo "PASSES must be >= 2 for the variance of the mean" >&2; exit 1; }
mkdir -p "$out"
out=$(cd "$out" && pwd)
depth=()
[ -n "${MAX_DEPTH:-}" ] && depth=(--max-depth "$MAX_DEPTH")
(cd "$ref" && "$py" mitsuba_ref.py cornell-box --variant llvm_ad_rgb --width "$w" --height "$h" \
    --spp "$spp" --passes "$passes" --seed "$seed" "${depth[@]}" \
    --out "$out/reference.exr" --var-out "$out/reference_var.exr" --png "$out/reference.png" \
    --json-out "$out/reference.json")
