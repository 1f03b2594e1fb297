#!/usr/bin/env bash
# The path-tracing kernel's instruction count on lavapipe, per scene, for one build or two.
#
# lavapipe runs the kernel as LLVM-compiled code on the CPU, so `valgrind --tool=callgrind`
# counts its instructions exactly, whatever else the machine does (its speed swings by 20-40%
# between rounds of one benchmark). The JIT-compiled code is callgrind's object of unknown name
# (`???`); this script sums it. Each scene renders one sample per pixel, which is one dispatch:
# the renderer sizes later dispatches by their measured time, so a render of several samples
# under valgrind's slowdown took a varying number of dispatches, and its count swung with them
# (the study scene at 64x64 and 16 spp: 63.8 and 71.7 M in two runs of one build; at 256x256 and
# 1 spp: 84.7 and 84.7 M). Same scene, method, size and seed for both builds: the same image.
#
# Needs valgrind and callgrind_annotate (Debian: valgrind).
# Usage: [OLD=path/to/pathlab] [NEW=target/release/pathlab] [METHOD=mis] [SIZE=256]
#        scripts/kernel_instructions.sh SCENE [SCENE ...]
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -gt 0 ] || { echo "usage: [OLD=...] $0 SCENE ..." >&2; exit 2; }
command -v valgrind >/dev/null && command -v callgrind_annotate >/dev/null \
    || { echo "kernel_instructions.sh needs valgrind (Debian: apt-get install valgrind)" >&2; exit 1; }
new=${NEW:-$(pwd)/target/release/pathlab}
old=${OLD:-}
method=${METHOD:-mis}
size=${SIZE:-256}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Million instructions of the JIT-compiled code in one render of $2 by build $1.
count() {
    valgrind --tool=callgrind --callgrind-out-file="$tmp/cg.out" "$1" render "$2" --method "$method" \
        --spp 1 --width "$size" --height "$size" --seed 3 -q -o "$tmp/image.exr" >/dev/null 2>"$tmp/err" \
        || { echo "render of $2 failed:" >&2; cat "$tmp/err" >&2; exit 1; }
    callgrind_annotate "$tmp/cg.out" | grep '\[???\]' | awk '{gsub(",", "", $1); s += $1} END {printf "%.1f", s / 1e6}'
}

if [ -n "$old" ]; then
    printf "%-44s %12s %12s %8s\n" "scene ($method, ${size}x$size, 1 spp)" "old M instr" "new M instr" "change"
else
    printf "%-44s %12s\n" "scene ($method, ${size}x$size, 1 spp)" "M instr"
fi
for scene in "$@"; do
    n=$(count "$new" "$scene")
    if [ -n "$old" ]; then
        o=$(count "$old" "$scene")
        printf "%-44s %12s %12s %7.1f%%\n" "$scene" "$o" "$n" "$(python3 -c "print(100 * ($n - $o) / $o)")"
    else
        printf "%-44s %12s\n" "$scene" "$n"
    fi
done
