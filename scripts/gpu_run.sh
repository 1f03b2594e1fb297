#!/usr/bin/env bash
# The prepared runs on a lent GPU machine behind the README's "On a GPU" numbers (2026-12-04),
# in one script. Prepare here, in the repository root (see ../shared/notes/gpu-device.md):
#   .gl/   the Vulkan loader packages (the device README's `apt-get download` line)
#   .gpu/  gzip'd stripped builds to compare, named by commit (BUILD.gz), and suite.gz, the
#          stripped test binary (`cargo test --release --no-run` names it); ico1.ply and
#          ico{1,8}.toml, the icosphere scenes of scripts/triangle_scaling.sh
# then call the device tool with carry [".gl", ".gpu"] and the command
#   BUILDS="e9f42f2 60012fe new" bash scripts/gpu_run.sh
# Everything it measures lands in $OUT: gpu.txt (driver), bench_study.json (every preset),
# bench.txt (meshes, builds alternated), truth.txt (the study's 100,000-spp reference), suite.txt.
set -u
for f in .gl/*.deb; do dpkg -x "$f" /; done; ldconfig
ls /usr/share/vulkan/icd.d/*nvidia* >/dev/null 2>&1 || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
O=${OUT:-/tmp/out}; mkdir -p "$O"
builds=${BUILDS:-new}
for b in $builds suite; do gunzip -c ".gpu/$b.gz" > "/tmp/$b" && chmod +x "/tmp/$b"; done
last=${builds##* }
nvidia-smi --query-gpu=name,driver_version,clocks.max.sm --format=csv > "$O/gpu.txt" 2>&1
"/tmp/$last" adapters >> "$O/gpu.txt" 2>&1
python3 scripts/icosphere_ply.py 8 .gpu/ico8.ply > /dev/null
timeout 100 "/tmp/$last" bench --seconds 1 --json > "$O/bench_study.json" 2> /dev/null
for m in best plain; do
  ( time timeout 60 "/tmp/$last" render assets/scenes/study.toml --method $m --spp 100000 -o /tmp/truth-$m.exr ) >> "$O/truth.txt" 2>&1
done
bench() { # build scene size label
  timeout 40 "/tmp/$1" bench "$2" --methods mis --size "$3" --seconds 1 --json 2>/dev/null | python3 -c "import json,sys; r=json.load(sys.stdin)[0]; print('$1 $4 $3 %.1f Msps %.1f Mrays' % (r['pixel_samples_per_second']/1e6, r['rays_per_second']/1e6))" >> "$O/bench.txt"
}
for round in 1 2; do for b in $builds; do
  bench "$b" assets/scenes/cornell_box.toml 1024x1024 cornell
  bench "$b" assets/scenes/veach_mis.xml 2048x1024 veach
  bench "$b" .gpu/ico1.toml 1024x1024 ico80
  bench "$b" .gpu/ico8.toml 1024x1024 ico1.3M
  bench "$b" assets/scenes/study.toml 1024x512 study
done; done
# The suite's binary runs `target/release/pathlab` under the path it was built at.
mkdir -p /work target/release && ln -sfn "$PWD" /work/main && cp "/tmp/$last" target/release/pathlab
timeout 270 /tmp/suite --test-threads 8 --skip viewer:: --skip deploy:: > "$O/suite.txt" 2>&1; echo "suite rc $?" >> "$O/suite.txt"
