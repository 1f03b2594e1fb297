#!/usr/bin/env bash
# Reference render of the lamps fixture, tests/fixtures/lamps/, by the reference renderer
# (Mitsuba 3.9.1, llvm_ad_rgb) loading assets/scenes/lamps.xml itself, the file pathlab reads
# (scripts/xml_reference.py: Mitsuba's -D for the size and depth; the file's box filter,
# independent sampler and path integrator): a tilted flat quad light and two smooth emissive
# icospheres (recomputed and given vertex normals; one-sided and two-sided BSDFs) over a floor.
# MAX_DEPTH (default 3), PASSES passes (default 64) of SPP samples per pixel (default 1024) at
# WIDTH x HEIGHT (default 64x48), seeds SEED, SEED+1, ... (default 0):
#   reference.exr      mean image: linear float32 RGB
#   reference_var.exr  per-pixel, per-channel variance of that mean (pass images' variance / PASSES)
#   reference.png      sRGB preview of the mean
#   reference.json     run record (mitsuba_version, size, spp, passes, seeds, timing, mean_rgb)
# into OUT (default tests/fixtures/lamps). Set-up of the reference renderer: see
# scripts/cornell_reference.sh.
#
# Usage: [WIDTH=w HEIGHT=h SPP=n PASSES=p SEED=s MAX_DEPTH=d OUT=dir] scripts/lamps_reference.sh
set -euo pipefail
cd "$(dirname "$0")/.."
py=${MITSUBA_PYTHON:-/tmp/mitsuba-venv/bin/python}
w=${WIDTH:-64}; h=${HEIGHT:-48}; spp=${SPP:-1024}; passes=${PASSES:-64}; seed=${SEED:-0}; depth=${MAX_DEPTH:-3}
out=${OUT:-tests/fixtures/lamps}
[ -x "$py" ] || { echo "no Mitsuba python at $py (see scripts/cornell_reference.sh)" >&2; exit 1; }
[ "$passes" -ge 2 ] || { echo "PASSES must be >= 2 for the variance of the mean" >&2; exit 1; }
mkdir -p "$out"
"$py" scripts/xml_reference.py assets/scenes/lamps.xml -D "resx=$w" -D "resy=$h" -D "max_depth=$depth" \
    --spp "$spp" --passes "$passes" --seed "$seed" \
    --out "$out/reference.exr" --var-out "$out/reference_var.exr" --png "$out/reference.png" \
    --json-out "$out/reference.json"
