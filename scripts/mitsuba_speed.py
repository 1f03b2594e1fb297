"""Mitsuba 3's render speed on one scene, for speed comparisons made elsewhere than this machine
(scripts/gpu_run.sh runs it with the cuda_ad_rgb variant on a lent GPU): load the scene once,
render once to compile Dr.Jit's kernels, then time ROUNDS renders of SPP samples per pixel and
print one JSON line with the median samples per second (render time only, as `pathlab bench`
reports its own).

The scene is a Mitsuba 3 XML file whose film size is the parameters `resx`/`resy` (as
assets/scenes/veach_mis.xml), or `cornell-box`: mi.cornell_box() with the comparison overrides
of the reference renderer's mitsuba_ref.py (box filter, independent sampler, max_depth 8).

    python scripts/mitsuba_speed.py cornell-box --variant cuda_ad_rgb --width 1024 --height 1024 \
        --spp 256 --ref ../shared/reference-renderer
"""
import argparse
import json
import os
import statistics
import sys


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--width", type=int, default=256)
    ap.add_argument("--height", type=int, default=256)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--max-depth", type=int, default=8, help="cornell-box only; an XML keeps its own")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--ref", default=os.path.join(os.path.dirname(__file__), "..", "..", "shared", "reference-renderer"),
                    help="the reference renderer's folder (mitsuba_ref.py, mitsuba_render.py)")
    args = ap.parse_args(argv)
    sys.path.insert(0, os.path.abspath(args.ref))
    import mitsuba_ref as ref  # noqa: E402  (picks a libLLVM for Dr.Jit's LLVM backend)

    mi, mr = ref.mi, ref.mr
    mi.set_variant(args.variant)
    if args.scene.endswith(".xml"):
        scene = mi.load_file(args.scene, resx=str(args.width), resy=str(args.height), spp=str(args.spp))
    else:
        scene = mi.load_dict(ref.scene_dict(args.scene, args.width, args.height, args.max_depth, args.spp))
    _, compile_s = mr.render_once(scene, args.spp, 1_000_003)
    times = [mr.render_once(scene, args.spp, seed)[1] for seed in range(args.rounds)]
    t = statistics.median(times)
    print(json.dumps({
        "renderer": "mitsuba", "mitsuba_version": mi.__version__, "variant": args.variant,
        "scene": os.path.basename(args.scene), "width": args.width, "height": args.height,
        "spp": args.spp, "first_render_s": round(compile_s, 3), "render_s": [round(x, 4) for x in times],
        "samples_per_s": args.width * args.height * args.spp / t,
    }))


if __name__ == "__main__":
    main()
