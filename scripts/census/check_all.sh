#!/usr/bin/env bash
# Which published Mitsuba 3 scenes pathlab loads: `pathlab check` on each of the 27 scene files of
# the census of 2026-12-03 (census-2026-12-03-before.md: sources, variants, every blocker), as
# extracted under $CENSUS (default /tmp/census) by extract.py from mirrors of
# mitsuba-renderer/mitsuba-data, mitsuba-renderer/mitsuba-tutorials,
# takkasila/practical_path_guiding_lab and niklassanden/ReSTIR_GI_DR (Bitterli's scenes for
# Mitsuba 3), with pathvariant.py's `.path.xml` copies where the integrator is not `path`.
# Prints LOADS or the first error per file, then the count.
#
# Usage: [CENSUS=dir] [PATHLAB=binary] scripts/census/check_all.sh
set -uo pipefail
census=${CENSUS:-/tmp/census}
pathlab=${PATHLAB:-$(cd "$(dirname "$0")/../.." && pwd)/target/release/pathlab}
files=(
  mitsuba-data/scenes/cbox/cbox.xml mitsuba-data/scenes/cbox/cbox-rgb.xml mitsuba-data/scenes/matpreview/matpreview.xml
  mitsuba-data/scenes/hello.path.xml mitsuba-data/docs/scenes/bsdf_roughplastic_ggx.xml mitsuba-data/docs/scenes/bsdf_conductor_aluminium.xml
  mitsuba-data/docs/scenes/bsdf_twosided_cbox.xml mitsuba-data/docs/scenes/texture_checkerboard.xml mitsuba-data/docs/scenes/shape_ply_bunny.xml
  mitsuba-data/docs/scenes/integrator_direct_both.path.xml mitsuba-data/tests/scenes/bsdf_spheres/test_roughdielectric_path.xml
  mitsuba-data/tests/scenes/various_shapes/test_various_shapes_path.xml mitsuba-data/tests/scenes/infinite_mirrors/scene_path.xml
  mitsuba-tutorials/scenes/cbox.xml mitsuba-tutorials/scenes/simple.path.xml mitsuba-tutorials/scenes/lego/scene.xml
  mitsuba-tutorials/scenes/shadow_art.path.xml practical_path_guiding_lab/scenes/cornell-box/scene.path.xml
  practical_path_guiding_lab/scenes/veach-ajar/scene.path.xml practical_path_guiding_lab/scenes/veach-bidir/scene.path.xml
  practical_path_guiding_lab/scenes/veach-mis/scene.path.xml practical_path_guiding_lab/scenes/teapot/scene_v3.path.xml
  practical_path_guiding_lab/scenes/torus/scene.path.xml ReSTIR_GI_DR/scenes/staircase2/scene.path.xml
  ReSTIR_GI_DR/scenes/living-room-2/scene.xml ReSTIR_GI_DR/scenes/dining_hall_chalice/scene.xml
  ReSTIR_GI_DR/scenes/cornell_box_picture/scene_picture.xml
)
loads=0
for f in "${files[@]}"; do
  if [ ! -f "$census/$f" ]; then echo "MISSING $f"; continue; fi
  first=$("$pathlab" check "$census/$f" 2>&1 | grep -v ': warning: ' | head -1)
  case "$first" in
    *": valid;"*) echo "LOADS   $f"; loads=$((loads + 1)) ;;
    *) echo "no      $f :: ${first#"$census/"}" ;;
  esac
done
echo "$loads of ${#files[@]} load"
