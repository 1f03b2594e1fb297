#!/usr/bin/env bash
# `pathlab check` on every documentation and test scene of mitsuba-data (docs/scenes and
# tests/scenes, without their include/ and fragments/ parts): each is copied with its includes
# and files by extract.py into /tmp/census/mitsuba-data/ (once), and each that fails prints its
# first error; a file whose only error is a `$spp` without a default (a fragment meant for
# `-D spp=...`, which Mitsuba needs too) is checked again with `--define spp=64`. The last line
# counts them.
#
# Usage: [BIN=path/to/pathlab] scripts/census/mitsuba_data_survey.sh MITSUBA_DATA_MIRROR
# (the bare mirror `fetch` makes of mitsuba-renderer/mitsuba-data). The numbers of 2026-12-05
# are in the README of this folder.
set -uo pipefail
cd "$(dirname "$0")/../.."
mirror=${1:?usage: scripts/census/mitsuba_data_survey.sh MITSUBA_DATA_MIRROR}
bin=${BIN:-target/release/pathlab}
ok=0; fail=0; with_spp=0
for f in $(git -C "$mirror" ls-tree -r HEAD --name-only | grep -E "^(docs/scenes|tests/scenes)/.*\.xml$" | grep -v "/include/\|/fragments/"); do
  [ -f "/tmp/census/mitsuba-data/$f" ] || python3 scripts/census/extract.py "$mirror" mitsuba-data "$f" >/dev/null 2>&1
  if out=$(timeout 120 "$bin" check "/tmp/census/mitsuba-data/$f" 2>&1); then
    ok=$((ok + 1))
  elif echo "$out" | grep -q '`$spp` has no value' && out=$(timeout 120 "$bin" check --define spp=64 "/tmp/census/mitsuba-data/$f" 2>&1); then
    # A fragment meant to be rendered with -D spp=... (Mitsuba needs it too): loads with one.
    ok=$((ok + 1)); with_spp=$((with_spp + 1))
    echo "ok with --define spp=64: $f"
  else
    fail=$((fail + 1))
    echo "FAIL $f: $(echo "$out" | grep -m1 'error' | sed 's/.*error: //' | cut -c1-150)"
  fi
done
echo "ok $ok (of which $with_spp with --define spp=64) fail $fail"
