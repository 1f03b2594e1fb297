#!/usr/bin/env bash
# Interleaved speed comparison on Veach's MIS scene (assets/scenes/veach_mis.xml, Mitsuba 3 XML):
# Mitsuba 3 (llvm_ad_rgb) loading the same file through scripts/xml_reference.py, and pathlab
# rendering it, both with -D resx=W -D resy=H (default 512x256), the file's max_depth, SPP
# samples per pixel (default 512; Mitsuba in passes of 64, its own sampler and filter as the file
# names them). pathlab is timed as a whole process (start-up, pipeline and readback included:
# ratio_to_mitsuba) and by its rendering alone (the EXR header's `pathlab:render_seconds`:
# rendering_ratio); Mitsuba reports its render time alone (`samples_per_s` of its JSON record,
# after its JIT warm-up), so the second is like for like. Samples per second compare the two only as far as their estimators do: pathlab's
# `mis` traces a shadow ray to each light (`--light-select all`), Mitsuba's `path` to one
# (`scripts/compare_mitsuba_efficiency.py` compares the time to an error instead). Only ratios
# within one round mean anything: the machine's speed swings with load.
#
# Set-up of the reference renderer: see scripts/compare_mitsuba.sh.
# PATHLAB=path/to/pathlab compares another build.
# Usage: [SPP=n] [W=512] [H=256] scripts/compare_mitsuba_veach.sh [ROUNDS] [METHODS...]   (default: 3 rounds, mis best)
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-3}
shift || true
methods=${*:-mis best}
py=${MITSUBA_PYTHON:-/tmp/mitsuba-venv/bin/python}
scene=$(pwd)/assets/scenes/veach_mis.xml
pathlab=${PATHLAB:-$(pwd)/target/release/pathlab}
[ -x "$pathlab" ] || cargo build --release
[ -x "$py" ] || { echo "no Mitsuba python at $py (see scripts/compare_mitsuba.sh)" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
w=${W:-512}; h=${H:-256}; spp=${SPP:-512}
pass_spp=$(( spp < 64 ? spp : 64 )); passes=$(( spp / pass_spp ))
echo "round,renderer,method,pixel_samples_per_second,ratio_to_mitsuba,rendering_samples_per_second,rendering_ratio"
for r in $(seq "$rounds"); do
    "$py" scripts/xml_reference.py "$scene" -D resx=$w -D resy=$h --spp $pass_spp --passes $passes \
        --out "$out/mi.exr" --json-out "$out/mi.json" >/dev/null 2>&1
    mi=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["samples_per_s"])' "$out/mi.json")
    echo "$r,mitsuba,path,$mi,1,$mi,1"
    for m in $methods; do
        t0=$(date +%s.%N)
        "$pathlab" render "$scene" -D resx=$w -D resy=$h --method "$m" --spp $(( pass_spp * passes )) -o "$out/p.exr" --quiet 2>/dev/null
        t1=$(date +%s.%N)
        rs=$("$py" -c 'import OpenEXR,sys; print(OpenEXR.File(sys.argv[1]).header()["pathlab:render_seconds"])' "$out/p.exr")
        python3 -c "n=$w*$h*$(( pass_spp * passes )); r=n/($t1-$t0); q=n/$rs; print(f'$r,pathlab,$m,{r:.0f},{r/$mi:.3f},{q:.0f},{q/$mi:.3f}')"
    done
done
