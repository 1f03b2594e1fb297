#!/bin/bash
# Submits a split render to Slurm: an array of SHARDS tasks, then the merge once all succeeded.
#
#   deploy/slurm/submit.sh SCENE.toml SPP SHARDS PARTS_DIR OUT.exr [render flags...]
#
# Prints the two job ids (array, merge). With WAIT=1 it blocks until the merge has finished
# and exits with its status.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
scene=$1 spp=$2 shards=$3 parts=$4 out=$5
shift 5
array=$(sbatch --parsable --array=0-$((shards - 1)) "$here/render-shard.sbatch" "$scene" "$spp" "$parts" "$@")
wait_flag=()
[ "${WAIT:-0}" = 1 ] && wait_flag=(--wait)
echo "array job $array"
merge=$(sbatch --parsable "${wait_flag[@]}" --dependency=afterok:"$array" "$here/merge.sbatch" "$parts" "$out" --variance)
echo "merge job $merge"
