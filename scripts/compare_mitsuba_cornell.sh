#!/usr/bin/env bash
# Interleaved speed comparison on Mitsuba 3's own Cornell box: pathlab rendering
# assets/scenes/cornell_box.toml against Mitsuba 3 (llvm_ad_rgb) rendering mi.cornell_box()
# through ../shared/reference-renderer/mitsuba_ref.py (box filter, independent sampler, its
# `path` integrator with max_depth 8 and Mitsuba's default Russian roulette from depth 5, which
# pathlab does not have yet), both at 256x256, max_depth 8, SPP samples per pixel (default 256,
# Mitsuba in passes of 64). pathlab is timed twice: as a whole process (start-up, BVH build,
# pipeline and readback included: ratio_to_mitsuba), and by its rendering alone (the EXR header's
# `pathlab:render_seconds`: rendering_ratio); Mitsuba reports its render time alone (after its
# JIT warm-up), so the second is like for like. Only ratios within one round mean anything: the
# machine's speed swings with load.
#
# Set-up of the reference renderer: see scripts/compare_mitsuba.sh.
# PATHLAB=path/to/pathlab compares another build.
# Usage: [SPP=n] scripts/compare_mitsuba_cornell.sh [ROUNDS] [METHODS...]   (default: 3 rounds, mis best)
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-3}
shift || true
methods=${*:-mis best}
py=${MITSUBA_PYTHON:-/tmp/mitsuba-venv/bin/python}
ref=${REFERENCE_RENDERER:-../shared/reference-renderer}
scene=$(pwd)/assets/scenes/cornell_box.toml
pathlab=${PATHLAB:-$(pwd)/target/release/pathlab}
[ -x "$pathlab" ] || cargo build --release
[ -x "$py" ] || { echo "no Mitsuba python at $py (see the set-up above)" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
w=256; h=256; spp=${SPP:-256}
pass_spp=$(( spp < 64 ? spp : 64 )); passes=$(( spp / pass_spp ))
echo "round,renderer,method,pixel_samples_per_second,ratio_to_mitsuba,rendering_samples_per_second,rendering_ratio"
for r in $(seq "$rounds"); do
    mi=$(cd "$ref" && "$py" mitsuba_ref.py cornell-box --variant llvm_ad_rgb --spp $pass_spp --passes $passes --width $w --height $h \
        --out "$out/mi.exr" --var-out "$out/mi_var.exr" 2>/dev/null | tail -n 1 | python3 -c 'import json,sys; print(json.load(sys.stdin)["samples_per_s"])')
    echo "$r,mitsuba,path,$mi,1,$mi,1"
    for m in $methods; do
        t0=$(date +%s.%N)
        "$pathlab" render "$scene" --method "$m" --width $w --height $h --spp $spp -o "$out/p.exr" --quiet 2>/dev/null
        t1=$(date +%s.%N)
        rs=$("$py" -c 'import OpenEXR,sys; print(OpenEXR.File(sys.argv[1]).header()["pathlab:render_seconds"])' "$out/p.exr")
        python3 -c "n=$w*$h*$spp; r=n/($t1-$t0); q=n/$rs; print(f'$r,pathlab,$m,{r:.0f},{r/$mi:.3f},{q:.0f},{q/$mi:.3f}')"
    done
done
