"""The cost of rendering from Python against the CLI: the study scene at 256x128, method best,
1 and 1024 spp, medians of 5 runs of each of

- cli:            `pathlab render` as a process (start, device, pipeline, render, EXR written);
- python, fresh:  a new Python process that imports pathlab, renders and writes the EXR;
- python, warm:   `pathlab.render` in a process that has rendered before (device and pipeline
                  reused), without and with `write_exr`;

with the render's own seconds (the `render_seconds` of the header) beside each.

    python scripts/python_overhead.py [--cli target/release/pathlab] [--runs 5]
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pathlab

REPO = Path(__file__).resolve().parents[1]
SCENE = REPO / "assets" / "scenes" / "study.toml"


def median_of(runs, f):
    walls, renders = [], []
    for _ in range(runs):
        wall, render = f()
        walls.append(wall)
        renders.append(render)
    return statistics.median(walls), statistics.median(renders)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--cli", default=str(REPO / "target" / "release" / "pathlab"))
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args()
    tmp = Path(tempfile.mkdtemp())
    out = tmp / "o.exr"
    scene = pathlab.load_scene(SCENE, width=256, height=128)
    pathlab.render(scene, "best", spp=1)  # the device and the pipeline, once

    print(f"adapter: {pathlab.device()['summary']}")
    print(f"{'spp':>5} | {'cli':>16} | {'python, fresh':>16} | {'python, warm':>16} | {'warm + write_exr':>16}")
    for spp in (1, 1024):
        def cli():
            t = time.perf_counter()
            subprocess.run([args.cli, "render", SCENE, "--width", "256", "--height", "128", "--spp", str(spp), "-q", "-o", out], check=True, capture_output=True)
            return time.perf_counter() - t, float(pathlab.read_exr(out).metadata["render_seconds"])

        code = (
            "import pathlab, sys; s = pathlab.load_scene(sys.argv[1], width=256, height=128); "
            "r = pathlab.render(s, 'best', spp=int(sys.argv[2])); pathlab.write_exr(sys.argv[3], r)"
        )

        def fresh():
            t = time.perf_counter()
            subprocess.run([sys.executable, "-c", code, SCENE, str(spp), out], check=True, capture_output=True)
            return time.perf_counter() - t, float(pathlab.read_exr(out).metadata["render_seconds"])

        def warm():
            t = time.perf_counter()
            r = pathlab.render(scene, "best", spp=spp)
            return time.perf_counter() - t, r.seconds

        def warm_write():
            t = time.perf_counter()
            r = pathlab.render(scene, "best", spp=spp)
            pathlab.write_exr(out, r)
            return time.perf_counter() - t, r.seconds

        cells = [median_of(args.runs, f) for f in (cli, fresh, warm, warm_write)]
        print(f"{spp:>5} | " + " | ".join(f"{w:7.3f} ({r:6.3f}) s" for w, r in cells))
    print("each cell: median wall time (median render_seconds), of", args.runs, "runs")


if __name__ == "__main__":
    main()
