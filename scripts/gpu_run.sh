#!/usr/bin/env bash
# The prepared run on a lent GPU machine behind the README's "On a GPU" numbers, in one script
# that stays inside its time (each step has its own limit; what ran lands in $OUT even if a later
# step is cut). Prepare here, in the repository root (see ../shared/notes/gpu-device.md):
#   .gl/   the Vulkan loader packages (the device README's `apt-get download` line)
#   .gpu/  pathlab.gz and suite.gz: the stripped, gzip'd `target/release/pathlab` and test binary
#          (`cargo test --release --no-run` names it); ico1.toml, ico8.toml and ico1.ply, the
#          icosphere scenes of scripts/triangle_scaling.sh; mitsuba.tar.xz, Mitsuba 3.9.1 and
#          Dr.Jit 1.5.0 for CPython 3.12 unpacked from their wheels with the variants other than
#          cuda_ad_rgb and scalar_rgb, headers and stubs taken out (22 MB); ref/, a copy of
#          ../shared/reference-renderer/{mitsuba_ref,mitsuba_render}.py
# then call the device tool with carry [".gl", ".gpu"] and the command `bash scripts/gpu_run.sh`.
# $OUT receives: gpu.txt (driver, adapters), versus_mitsuba.txt (pathlab against Mitsuba's
# cuda_ad_rgb, render time only, median of 3), bench_study.json (every preset), bench.txt
# (meshes and the material fixtures, mis), chi2.txt (the two test files that failed there
# before, with their messages), suite.txt (the rest of the suite, in the time left).
set -u
start=$SECONDS
left() { echo $(( ${BUDGET:-390} - (SECONDS - start) )); }
for f in .gl/*.deb; do dpkg -x "$f" /; done; ldconfig
ls /usr/share/vulkan/icd.d/*nvidia* >/dev/null 2>&1 || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
O=${OUT:-/tmp/out}; mkdir -p "$O"
for b in pathlab suite; do gunzip -c ".gpu/$b.gz" > "/tmp/$b" && chmod +x "/tmp/$b"; done
P=/tmp/pathlab
nvidia-smi --query-gpu=name,driver_version,clocks.max.sm --format=csv > "$O/gpu.txt" 2>&1
$P adapters >> "$O/gpu.txt" 2>&1

# pathlab against Mitsuba 3 (cuda_ad_rgb, OptiX) on Mitsuba's Cornell box and Veach's scene.
mkdir -p /tmp/site && tar xJf .gpu/mitsuba.tar.xz -C /tmp/site
versus() { # scene-for-pathlab scene-for-mitsuba WxH spp label
  local w=${3%x*} h=${3#*x}
  timeout 40 $P bench "$1" --methods mis --size "$3" --seconds 2 --json 2>/dev/null | python3 -c "import json,sys; r=json.load(sys.stdin)[0]; print('$5 $3 pathlab mis %.1f M samples/s' % (r['pixel_samples_per_second']/1e6))" >> "$O/versus_mitsuba.txt"
  PYTHONPATH=/tmp/site timeout 90 python3 scripts/mitsuba_speed.py "$2" --variant cuda_ad_rgb --width "$w" --height "$h" --spp "$4" --ref .gpu/ref >> "$O/versus_mitsuba.txt" 2>> "$O/mitsuba_err.txt"
}
versus assets/scenes/cornell_box.toml cornell-box 1024x1024 256 cornell
versus assets/scenes/veach_mis.xml assets/scenes/veach_mis.xml 2048x1024 64 veach
echo "after versus: $(left) s left" >> "$O/gpu.txt"

timeout 60 $P bench --seconds 1 --json > "$O/bench_study.json" 2> /dev/null
bench() { # scene size label
  timeout 30 $P bench "$1" --methods mis --size "$2" --seconds 1 --json 2>/dev/null | python3 -c "import json,sys; r=json.load(sys.stdin)[0]; print('$3 $2 %.1f Msps %.1f Mrays' % (r['pixel_samples_per_second']/1e6, r['rays_per_second']/1e6))" >> "$O/bench.txt"
}
python3 scripts/icosphere_ply.py 8 .gpu/ico8.ply > /dev/null
bench assets/scenes/cornell_box.toml 1024x1024 cornell
bench assets/scenes/veach_mis.xml 2048x1024 veach
bench .gpu/ico1.toml 1024x1024 ico80
bench .gpu/ico8.toml 1024x1024 ico1.3M
bench assets/scenes/study.toml 1024x512 study
for f in mask/mask.xml twosided/twosided.xml rough_textures/rough_textures.xml cornell_textured_layers/cornell_textured_layers.xml cornell_rough_glass/cornell_rough_glass.xml; do
  [ -f "tests/fixtures/$f" ] && bench "tests/fixtures/$f" 512x512 "${f%%/*}"
done
echo "after bench: $(left) s left" >> "$O/gpu.txt"

# The suite's binary runs `target/release/pathlab` under the path it was built at.
mkdir -p /work target/release && ln -sfn "$PWD" /work/main && cp $P target/release/pathlab
timeout 70 /tmp/suite --test-threads 4 --nocapture chi2_sampling:: sampler_twin:: > "$O/chi2.txt" 2>&1; echo "rc $?" >> "$O/chi2.txt"
t=$(left); [ "$t" -gt 30 ] || t=30
timeout "$t" /tmp/suite --test-threads 16 --skip viewer --skip deploy --skip chi2_sampling:: --skip sampler_twin:: > "$O/suite.txt" 2>&1; echo "suite rc $? after $((SECONDS - start)) s" >> "$O/suite.txt"
