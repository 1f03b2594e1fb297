#!/usr/bin/env bash
# pathlab's speed against Mitsuba 3.9.1 on each published scene file that `pathlab check` loads
# (the census's files under $CENSUS, default /tmp/census; see check_all.sh), at the scene's own
# size and depth: Mitsuba's `path` integrator (llvm_ad_rgb, speed.py: the best of 2 timed renders
# of SPP samples per pixel after one to compile) against `pathlab bench SCENE --methods mis`
# (SECONDS of rendering after a warm-up, device time). Both exclude start-up and compilation.
# Prints a Markdown table. Only ratios within one run mean anything: the machine's speed swings
# with load.
#
# Usage: [CENSUS=dir] [SPP=n] [SECONDS=s] scripts/census/speed.sh
set -uo pipefail
cd "$(dirname "$0")/../.."
census=${CENSUS:-/tmp/census}
py=${MITSUBA_PYTHON:-/tmp/mitsuba-venv/bin/python}
pathlab=$(pwd)/target/release/pathlab
spp=${SPP:-16}; seconds=${SECONDS_EACH:-3}
echo "| file | size | Mitsuba M samples/s | pathlab mis M samples/s | pathlab / Mitsuba |"
echo "|---|---|---|---|---|"
for f in $(scripts/census/check_all.sh 2>/dev/null | awk '$1=="LOADS"{print $2}'); do
  s="$census/$f"
  mi=$("$py" scripts/census/speed.py "$s" --spp "$spp" 2>/dev/null | tail -n 1)
  [ -n "$mi" ] || { echo "| \`$f\` | | Mitsuba failed | | |"; continue; }
  read -r w h mis < <(python3 -c "import json,sys; j=json.loads(sys.argv[1]); print(j['width'], j['height'], j['samples_per_s']/1e6)" "$mi")
  pl=$("$pathlab" bench "$s" --methods mis --size "${w}x${h}" --seconds "$seconds" 2>/dev/null | awk '$1=="mis"{print $4}')
  python3 -c "import sys; m=float(sys.argv[2]); p=float(sys.argv[3]) if sys.argv[3] else float('nan'); print(f'| \`{sys.argv[1]}\` | {sys.argv[4]} | {m:.3f} | {p:.3f} | {p/m:.2f}x |')" "$f" "$mis" "$pl" "${w}x${h}"
done
