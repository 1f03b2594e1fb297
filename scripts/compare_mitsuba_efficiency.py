"""Equal-error speed against Mitsuba 3: the seconds each renderer needs to reach one relMSE on the
same scene, not only its samples per second (issue 31).

Samples per second compare renderers only where their estimators have the same variance per
sample. pathlab's `mis` traces a shadow ray to every spherical light (`--light-select all`,
its default there), Mitsuba's `path` to one; pathlab's `mis+uniform` is Mitsuba's estimator.
What a user waits for is an image of a given error, so this script measures, for each renderer,
the relMSE of its image and the seconds it took, and from them the seconds to reach the target
relMSE (relMSE falls as 1 / samples, so seconds x relMSE / target).

Both renderers are treated alike:
- Each renders PASSES passes with independent seeds (pathlab: `--seed k`; Mitsuba:
  `mitsuba_ref.py`'s passes), and each pixel's variance of the mean comes from the spread of
  its passes (n - 1 in the denominator), the same estimator for both. Each round takes fresh
  seeds, so the median over rounds averages the relMSE estimates' own noise too.
- The relMSE is pathlab's `estimate::rel_mse_from_variance`: per channel, var / (max(mean^2 -
  var, 0) + 0.01), averaged over channels and pixels.
- Seconds are rendering alone: pathlab's header `pathlab:render_seconds` (after the pipeline
  is created), Mitsuba's passes after its JIT warm-up (`mitsuba_ref.py`'s `render_s`). pathlab's
  whole process (start-up and pipeline creation included) is reported beside it.

Rounds alternate the renderers; only ratios within a round mean anything (this machine's speed
swings with load).

    /tmp/mitsuba-venv/bin/python scripts/compare_mitsuba_efficiency.py [--rounds 3] \
        [--target 1e-3] [--scenes cornell,veach] [--methods mis,mis+uniform,best] [--first-seed 1] \
        [--spp-scale 1]

Output: CSV lines round, scene, renderer, method, spp, seconds, whole-process seconds, relMSE,
seconds to the target, Mitsuba's seconds to it / this one's (above 1: faster than Mitsuba).
PATHLAB= picks a build, REFERENCE_RENDERER= the reference renderer's folder.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
import OpenEXR

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
REF = os.environ.get("REFERENCE_RENDERER", os.path.join(ROOT, "..", "shared", "reference-renderer"))
PATHLAB = os.environ.get("PATHLAB", os.path.join(ROOT, "target", "release", "pathlab"))
REL_MSE_EPSILON = 0.01  # src/metrics/linear.rs

# name: (pathlab scene and flags, Mitsuba arguments, spp per pass, passes)
SCENES = {
    # Mitsuba's own Cornell box, mi.cornell_box() (max_depth 8, roulette from depth 5), and
    # pathlab's shape-for-shape copy of it; 256x256 as scripts/compare_mitsuba_cornell.sh.
    "cornell": (
        ["assets/scenes/cornell_box.toml", "--width", "256", "--height", "256"],
        [os.path.join(REF, "mitsuba_ref.py"), "cornell-box", "--width", "256", "--height", "256"],
        32,
        8,
    ),
    # Veach's MIS scene at 512x256, both loading the same XML file.
    "veach": (
        ["assets/scenes/veach_mis.xml", "-D", "resx=512", "-D", "resy=256"],
        [os.path.join(HERE, "xml_reference.py"), os.path.join(ROOT, "assets/scenes/veach_mis.xml"), "-D", "resx=512", "-D", "resy=256"],
        8,
        8,
    ),
}


def read_rgb(path):
    """The R, G, B channels of an EXR as an (H, W, 3) float64 array."""
    with OpenEXR.File(path) as f:
        channels = f.channels()
        if "RGB" in channels:
            return np.asarray(channels["RGB"].pixels, dtype=np.float64)
        return np.stack([np.asarray(channels[c].pixels, dtype=np.float64) for c in "RGB"], axis=-1)


def header_seconds(path):
    with OpenEXR.File(path) as f:
        return float(f.header()["pathlab:render_seconds"])


def rel_mse(mean, var_mean):
    """pathlab's estimate::rel_mse_from_variance."""
    return float(np.mean(var_mean / (np.maximum(mean * mean - var_mean, 0.0) + REL_MSE_EPSILON)))


def mean_and_variance(passes):
    """The mean of the passes and each pixel's variance of that mean (n - 1 in the denominator)."""
    stack = np.stack(passes)
    n = stack.shape[0]
    return stack.mean(axis=0), stack.var(axis=0, ddof=1) / n


def run_pathlab(scene, method, spp, passes, first_seed, out):
    images, seconds, t0 = [], 0.0, time.perf_counter()
    flags, _, _, _ = SCENES[scene]
    for k in range(passes):
        path = os.path.join(out, f"p{k}.exr")
        subprocess.run([PATHLAB, "render", *flags, "--method", method, "--spp", str(spp), "--seed", str(first_seed + k), "-o", path, "--quiet"],
                       cwd=ROOT, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        images.append(read_rgb(path))
        seconds += header_seconds(path)
    whole = time.perf_counter() - t0
    mean, var = mean_and_variance(images)
    return seconds, whole, rel_mse(mean, var)


def run_mitsuba(scene, spp, passes, first_seed, out):
    _, args, _, _ = SCENES[scene]
    mean_path, var_path = os.path.join(out, "mi.exr"), os.path.join(out, "mi_var.exr")
    t0 = time.perf_counter()
    res = subprocess.run([sys.executable, *args, "--spp", str(spp), "--passes", str(passes), "--seed", str(first_seed), "--out", mean_path, "--var-out", var_path],
                         cwd=REF, check=True, capture_output=True, text=True)
    whole = time.perf_counter() - t0
    record = json.loads(res.stdout.strip().splitlines()[-1])
    return record["render_s"], whole, rel_mse(read_rgb(mean_path), read_rgb(var_path))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--target", type=float, default=1e-3, help="the relMSE both renderers are timed to")
    ap.add_argument("--scenes", default="cornell,veach")
    ap.add_argument("--methods", default="mis,mis+uniform,best")
    ap.add_argument("--spp-scale", type=int, default=1,
                    help="multiply both renderers' samples per pass: at the default, Veach's passes of 8 spp "
                         "take pathlab under half a second each, of which its first dispatch's compilation "
                         "by lavapipe is a share that Mitsuba's excluded JIT warm-up does not pay")
    ap.add_argument("--first-seed", type=int, default=1, help="round r's passes use seeds first + 1000 (r - 1), + 1, ...")
    args = ap.parse_args()
    if not os.access(PATHLAB, os.X_OK):
        sys.exit(f"no pathlab at {PATHLAB} (cargo build --release, or PATHLAB=)")
    scenes = args.scenes.split(",")
    for s in scenes:
        if s not in SCENES:
            sys.exit(f"unknown scene {s!r} (known: {', '.join(SCENES)})")
    print("round,scene,renderer,method,spp,seconds,whole_seconds,rel_mse,seconds_to_target,mitsuba_over_this", flush=True)
    with tempfile.TemporaryDirectory() as out:
        for r in range(1, args.rounds + 1):
            for s in scenes:
                _, _, spp, passes = SCENES[s]
                spp *= args.spp_scale
                # Each round a fresh set of seeds: a relMSE estimated from one set swings by 10-20%
                # on Veach's scene (its glossy highlights of small lights are heavy-tailed).
                seed = args.first_seed + 1000 * (r - 1)
                secs, whole, err = run_mitsuba(s, spp, passes, seed, out)
                mi_to_target = secs * err / args.target
                print(f"{r},{s},mitsuba,path,{spp * passes},{secs:.3f},{whole:.3f},{err:.4e},{mi_to_target:.3f},1", flush=True)
                for m in args.methods.split(","):
                    secs, whole, err = run_pathlab(s, m, spp, passes, seed, out)
                    to_target = secs * err / args.target
                    print(f"{r},{s},pathlab,{m},{spp * passes},{secs:.3f},{whole:.3f},{err:.4e},{to_target:.3f},{mi_to_target / to_target:.3f}", flush=True)


if __name__ == "__main__":
    main()
