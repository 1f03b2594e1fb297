#!/usr/bin/env bash
# How the cost of a ray grows with the number of triangles: one scene per size, a subdivided
# icosphere (scripts/icosphere_ply.py, 20 * 4^k triangles) filling most of the view under a
# spherical light, rendered with `mis` at 256x256, max_depth 3. For each size: BVH build time
# and GPU memory (`pathlab check`), and rays per second (`pathlab bench`). Only ratios within
# one run mean anything: the machine's speed swings with load.
#
# PATHLAB=path/to/pathlab measures another build; KEEP=dir keeps the scenes.
# Usage: [SECONDS=3] [LEVELS="2 3 5 6 8"] scripts/triangle_scaling.sh
set -euo pipefail
cd "$(dirname "$0")/.."
pathlab=${PATHLAB:-$(pwd)/target/release/pathlab}
[ -x "$pathlab" ] || cargo build --release
seconds=${SECONDS_PER_SIZE:-${SECONDS:-3}}
levels=${LEVELS:-2 3 5 6 8}
# KEEP=dir keeps the scenes there (sceneK.toml and icoK.ply), for scripts/compare_builds.sh.
if [ -n "${KEEP:-}" ]; then
    dir=$KEEP
    mkdir -p "$dir"
else
    dir=$(mktemp -d)
    trap 'rm -rf "$dir"' EXIT
fi
echo "triangles,bvh_nodes,bvh_depth,build_ms,gpu_mib,M_rays_per_s,M_samples_per_s"
for k in $levels; do
    python3 scripts/icosphere_ply.py "$k" "$dir/ico$k.ply"
    cat > "$dir/scene$k.toml" <<TOML
[camera]
position = [0, 0, 3]
look_at = [0, 0, 0]
up = [0, 1, 0]
fov_x = 45
[render]
width = 256
height = 256
max_depth = 3
environment = 0.1
[materials.grey]
diffuse = 0.6
[materials.lamp]
emission = 20
[[meshes]]
file = "ico$k.ply"
material = "grey"
# Flat, as measured before meshes without normals were given smooth ones (Mitsuba's rule).
face_normals = true
[[spheres]]
center = [1.5, 1.5, 1.5]
radius = 0.3
material = "lamp"
TOML
    bvh=$("$pathlab" check "$dir/scene$k.toml" | grep '^BVH')
    tris=$(echo "$bvh" | sed -E 's/BVH: ([0-9]+) triangles.*/\1/')
    nodes=$(echo "$bvh" | sed -E 's/.* ([0-9]+) nodes.*/\1/')
    depth=$(echo "$bvh" | sed -E 's/.*depth ([0-9]+).*/\1/')
    ms=$(echo "$bvh" | sed -E 's/.*built in ([0-9.]+) ms.*/\1/')
    mib=$(echo "$bvh" | sed -E 's/.*GPU memory ([0-9.]+) MiB.*/\1/')
    rec=$("$pathlab" bench "$dir/scene$k.toml" --methods mis --size 256x256 --seconds "$seconds" --json 2>/dev/null)
    rays=$(echo "$rec" | python3 -c 'import json,sys; r=json.load(sys.stdin)[0]; print("%.3f,%.3f" % (r["rays_per_second"] / 1e6, r["pixel_samples_per_second"] / 1e6))')
    echo "$tris,$nodes,$depth,$ms,$mib,$rays"
done
