#!/usr/bin/env bash
# Interleaved speed comparison with the reference renderer (Mitsuba 3, llvm_ad_rgb) on the same
# machine: the study scene at 256x128, max_depth 3, SPP samples per pixel (default 1024; Mitsuba
# renders them as passes of 256, which keeps its wavefront in memory). pathlab is timed as a whole process
# (start-up, adapter, pipeline and readback included); Mitsuba reports its render time alone
# (after its JIT warm-up), as its script prints it. Only ratios within one round mean anything:
# the machine's speed swings with load.
#
# Set-up of the reference renderer (once per machine), from ../shared/reference-renderer/README.md:
#   apt-get install -y libllvm19
#   python3 -m venv /tmp/mitsuba-venv && /tmp/mitsuba-venv/bin/pip install -r ../shared/reference-renderer/requirements.txt
#
# Usage: [SPP=n] scripts/compare_mitsuba.sh [ROUNDS] [METHODS...]   (default: 3 rounds, plain mis best)
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-3}
shift || true
methods=${*:-plain mis best}
py=${MITSUBA_PYTHON:-/tmp/mitsuba-venv/bin/python}
ref=${REFERENCE_RENDERER:-../shared/reference-renderer}
scene=$(pwd)/assets/scenes/study.toml
pathlab=$(pwd)/target/release/pathlab
[ -x "$pathlab" ] || cargo build --release
[ -x "$py" ] || { echo "no Mitsuba python at $py (see the set-up above)" >&2; exit 1; }
out=$(mktemp -d)
w=256; h=128; spp=${SPP:-1024}; depth=3
pass_spp=$(( spp < 256 ? spp : 256 )); passes=$(( spp / pass_spp ))
echo "round,renderer,method,pixel_samples_per_second,ratio_to_mitsuba"
for r in $(seq "$rounds"); do
    mi=$(cd "$ref" && "$py" mitsuba_seed.py "$scene" --variant llvm_ad_rgb --spp $pass_spp --passes $passes --width $w --height $h \
        --max-depth $depth --out "$out/mi.exr" 2>/dev/null | tail -n 1 | python3 -c 'import json,sys; print(json.load(sys.stdin)["samples_per_s"])')
    echo "$r,mitsuba,path,$mi,1"
    for m in $methods; do
        t0=$(date +%s.%N)
        "$pathlab" render "$scene" --method "$m" --width $w --height $h --max-depth $depth --spp $spp -o "$out/p.exr" --quiet 2>/dev/null
        t1=$(date +%s.%N)
        python3 -c "r=$w*$h*$spp/($t1-$t0); print(f'$r,pathlab,$m,{r:.0f},{r/$mi:.3f}')"
    done
done
rm -rf "$out"
