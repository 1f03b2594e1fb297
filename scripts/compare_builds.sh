#!/usr/bin/env bash
# Samples per second of two builds on the same scenes, alternated in rounds of one run (the
# machine's speed swings between rounds; only a build's median against the other's in the same
# run means anything). Each line: round, build, scene, M samples/s, M rays/s.
#
# Usage: OLD=path/to/pathlab [NEW=target/release/pathlab] [ROUNDS=3] [SECS=2] [METHOD=mis]
#        scripts/compare_builds.sh SCENE:WxH [SCENE:WxH ...]
# The README's stackless-traversal numbers (2026-12-04): the icospheres of
# scripts/triangle_scaling.sh (scripts/icosphere_ply.py 1, 5, 8 into its scene) at 256x256,
# assets/scenes/veach_mis.xml:512x256, assets/scenes/cornell_box.toml:256x256 and
# assets/scenes/study.toml:256x128.
set -euo pipefail
cd "$(dirname "$0")/.."
old=${OLD:?OLD=path/to/the/other/pathlab}
new=${NEW:-$(pwd)/target/release/pathlab}
[ $# -gt 0 ] || { echo "usage: OLD=... $0 SCENE:WxH ..." >&2; exit 2; }
for round in $(seq "${ROUNDS:-3}"); do
  for sc in "$@"; do
    scene=${sc%:*}; size=${sc##*:}
    for build in OLD NEW; do
      bin=$old; [ $build = NEW ] && bin=$new
      "$bin" bench "$scene" --methods "${METHOD:-mis}" --size "$size" --seconds "${SECS:-2}" --json 2>/dev/null |
        python3 -c "import json,sys; r=json.load(sys.stdin)[0]; print('%s %s %-40s %8.3f M samples/s %8.3f M rays/s' % (sys.argv[1], sys.argv[2], sys.argv[3], r['pixel_samples_per_second']/1e6, r['rays_per_second']/1e6))" "$round" "$build" "$scene"
    done
  done
done
