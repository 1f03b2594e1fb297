"""What the scripts that record Mitsuba 3.9.1's own BSDF values share (roughplastic_evals.py,
principled_evals.py): pairs of directions in the BSDF's local frame (+z the normal), each with
Mitsuba's eval divided by cos(wi) and its pdf, and the fixture's writing. `wo` is pathlab's (the
viewer's direction, Mitsuba's si.wi), `wi` the scattered one (Mitsuba's wo)."""
import json
import math
import os
import sys

import mitsuba as mi

ANGLES = [0.0, 20.0, 45.0, 70.0, 85.0, 89.5]


def direction(theta, phi):
    t, p = math.radians(theta), math.radians(phi)
    return [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]


def pairs(bsdf, wi_azimuth):
    """Every (wo, wi) of ANGLES x ANGLES, wo at azimuth 10 degrees, wi at wi_azimuth(k) for the
    k-th angle, with Mitsuba's f = eval / cos(wi) (0 below the surface) and pdf."""
    ctx = mi.BSDFContext()
    out = []
    for a in ANGLES:
        for k, b in enumerate(ANGLES):
            wo = direction(a, 10.0)
            wi = direction(b, wi_azimuth(k))
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(wo)
            si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
            value = bsdf.eval(ctx, si, mi.Vector3f(wi))
            pdf = bsdf.pdf(ctx, si, mi.Vector3f(wi))
            cos = wi[2]
            f = [float(value[c]) / cos if cos > 0 else 0.0 for c in range(3)]
            out.append({"wo": wo, "wi": wi, "f": f, "pdf": float(pdf)})
    return out


def write(out, name):
    """Writes `out` as tests/fixtures/NAME."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fixtures", name)
    with open(path, "w") as fh:
        json.dump(out, fh, separators=(",", ":"))
        fh.write("\n")
    print(f"wrote {os.path.normpath(path)}", file=sys.stderr)
