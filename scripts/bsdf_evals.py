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


def pairs_both_sides(bsdf, wi_azimuth):
    """`pairs`, then the same with wi below the surface (transmission), then with wo below (the
    viewer behind the surface: pathlab's `inside`) and wi on either side: f = eval / |cos(wi)|."""
    ctx = mi.BSDFContext()
    out = []
    for wo_sign, wi_sign in [(1, 1), (1, -1), (-1, -1), (-1, 1)]:
        for a in ANGLES:
            for k, b in enumerate(ANGLES):
                wo = direction(a, 10.0)
                wi = direction(b, wi_azimuth(k))
                wo[2] *= wo_sign
                wi[2] *= wi_sign
                si = mi.SurfaceInteraction3f()
                si.wi = mi.Vector3f(wo)
                si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
                value = bsdf.eval(ctx, si, mi.Vector3f(wi))
                pdf = bsdf.pdf(ctx, si, mi.Vector3f(wi))
                cos = abs(wi[2])
                f = [float(value[c]) / cos if cos > 0 else 0.0 for c in range(3)]
                out.append({"wo": wo, "wi": wi, "f": f, "pdf": float(pdf)})
    return out


def record(plugin, configs, name, both_sides=False):
    """Each config's properties (floats; a list is an RGB) on Mitsuba's `plugin`, its pairs
    (`pairs`, or `pairs_both_sides`) near the mirror direction for some (the specular peaks)
    and elsewhere for others, written as tests/fixtures/NAME."""
    out = {"mitsuba": mi.__version__, "variant": "scalar_rgb", "configs": []}
    for config in configs:
        d = {"type": plugin}
        for k, v in config.items():
            d[k] = {"type": "rgb", "value": v} if isinstance(v, list) else v
        azimuth = lambda k: 190.0 + 3.0 * k if k % 2 == 0 else 200.0 + 37.0 * k  # noqa: E731
        pairs_of = pairs_both_sides if both_sides else pairs
        out["configs"].append({"properties": config, "pairs": pairs_of(mi.load_dict(d), azimuth)})
    write(out, name)


def write(out, name):
    """Writes `out` as tests/fixtures/NAME."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fixtures", name)
    with open(path, "w") as fh:
        json.dump(out, fh, separators=(",", ":"))
        fh.write("\n")
    print(f"wrote {os.path.normpath(path)}", file=sys.stderr)
