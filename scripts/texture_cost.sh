#!/usr/bin/env bash
# The cost of bitmap lookups: `pathlab bench` on the Cornell box of tests/fixtures/cornell_bitmap/
# with its four textures replaced (a) by one 512x512 PNG of a constant sRGB code (188) and (b)
# by that code's linear value as a constant colour. The light transport is the same; the
# difference is the lookups (uvs, four texel fetches, the decode table, the filter). (c) a
# checkerboard of that one colour: the cost of the uvs and of resolving a texture slot alone.
#
# Usage: [METHODS=mis] [SIZE=256x256] [BENCH_SECONDS=5] scripts/texture_cost.sh
set -euo pipefail
cd "$(dirname "$0")/.."
pathlab=${PATHLAB:-target/release/pathlab}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 - "$dir" <<'PY'
import re, struct, sys, zlib
d = sys.argv[1]
w = h = 512
raw = b"".join(b"\x00" + bytes([188, 188, 188]) * w for _ in range(h))
def chunk(t, data):
    return struct.pack(">I", len(data)) + t + data + struct.pack(">I", zlib.crc32(t + data) & 0xffffffff)
png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")
open(f"{d}/constant.png", "wb").write(png)
xml = open("tests/fixtures/cornell_bitmap/cornell_bitmap.xml").read()
v = 188 / 255
linear = ((v + 0.055) / 1.055) ** 2.4
pattern = re.compile(r'<texture name="reflectance" type="bitmap">.*?</texture>', re.S)
textured = pattern.sub('<texture name="reflectance" type="bitmap"><string name="filename" value="constant.png"/></texture>', xml)
constant = pattern.sub(f'<rgb name="reflectance" value="{linear:.9f}"/>', xml)
open(f"{d}/textured.xml", "w").write(textured)
open(f"{d}/constant.xml", "w").write(constant)
# The same with a checkerboard of one colour: the uvs' cost without the bitmap's lookups.
checker = pattern.sub(f'<texture name="reflectance" type="checkerboard"><rgb name="color0" value="{linear:.9f}"/><rgb name="color1" value="{linear:.9f}"/></texture>', xml)
open(f"{d}/checkerboard.xml", "w").write(checker)
PY
for scene in constant checkerboard textured; do
  echo "== $scene"
  "$pathlab" bench "$dir/$scene.xml" --methods "${METHODS:-mis}" --size "${SIZE:-256x256}" --seconds "${BENCH_SECONDS:-5}"
done
