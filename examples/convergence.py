"""Convergence of three methods on the study scene: each renders progressively (pathlab.Renderer,
doubling its samples), is scored against a reference after every step, and its relative MSE is
plotted against seconds of rendering. Saves a PNG.

    pip install ./python matplotlib
    python examples/convergence.py [--out convergence.png] [--size 256x128] [--reference-spp 4096]
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import pathlab  # noqa: E402

HERE = Path(__file__).resolve().parent
METHODS = ["plain", "nee", "mis"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default=str(HERE.parent / "assets" / "scenes" / "study.toml"))
    parser.add_argument("--out", default="convergence.png")
    parser.add_argument("--size", default="256x128")
    parser.add_argument("--reference-spp", type=int, default=4096)
    parser.add_argument("--max-spp", type=int, default=1024)
    args = parser.parse_args()
    width, height = (int(v) for v in args.size.split("x"))

    scene = pathlab.load_scene(args.scene, width=width, height=height)
    reference = pathlab.render(scene, "best", spp=args.reference_spp, seed=1000, progress=True)
    print(f"reference: {reference.spp} spp of best in {reference.seconds:.1f} s")

    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=120)
    for method in METHODS:
        r = pathlab.Renderer(scene, method, seed=0)
        seconds, errors = [], []
        step = 1
        while r.spp < args.max_spp:
            r.add(step)
            seconds.append(r.seconds)
            errors.append(pathlab.metrics.rel_mse(r.image, reference.image))
            step = r.spp  # double the total
        print(f"{method}: {r.spp} spp in {r.seconds:.2f} s, relMSE {errors[-1]:.3e}")
        ax.loglog(seconds, errors, marker="o", markersize=3, label=method)
    ax.set_xlabel("seconds of rendering")
    ax.set_ylabel("relative MSE against the reference")
    ax.set_title(f"study scene {width}x{height} on {pathlab.device()['name']}", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
