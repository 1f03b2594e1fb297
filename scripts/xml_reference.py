"""Reference render of a Mitsuba 3 XML scene, loaded by Mitsuba itself from the same file pathlab
reads, with `-D name=value` parameters (Mitsuba's own -D: image size, max_depth, ...). Everything
else is the reference renderer's mitsuba_ref.py (../shared/reference-renderer): passes with
independent seeds, the mean (linear float32 RGB EXR), the per-pixel variance of the mean, a PNG
preview and a JSON run record. The scene's own pixel filter and sampler are used: pathlab's
shipped XML scenes say <rfilter type="box"/> and <sampler type="independent">.

    MITSUBA_PYTHON=/tmp/mitsuba-venv/bin/python
    $MITSUBA_PYTHON scripts/xml_reference.py assets/scenes/veach_mis.xml -D resx=128 -D resy=72 \
        --spp 1024 --passes 64 --out ref.exr --var-out ref_var.exr --json-out ref.json
(`--spp` is the per-pass sample count, passed to the scene as $spp.)
"""
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.environ.get("REFERENCE_RENDERER", os.path.join(here, "..", "..", "shared", "reference-renderer")))
import mitsuba_ref  # noqa: E402

params, rest, argv = {}, [], sys.argv[1:]
while argv:
    a = argv.pop(0)
    if a in ("-D", "--define"):
        k, v = argv.pop(0).split("=", 1)
        params[k] = v
    else:
        rest.append(a)


def load(args):
    scene = os.path.abspath(args.scene)
    return mitsuba_ref.mi.load_file(scene, spp=str(args.spp), **params)


mitsuba_ref.load = load
mitsuba_ref.main(rest)
