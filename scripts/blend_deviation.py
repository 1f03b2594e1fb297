#!/usr/bin/env python3
"""Where Mitsuba 3.9.1's own `blendbsdf` image is off the blend's definition, measured against
pathlab (README, the `blendbsdf` row of the Mitsuba table). Run with the reference renderer's venv
and a built pathlab:

    /tmp/mitsuba-venv/bin/python scripts/blend_deviation.py delta
    /tmp/mitsuba-venv/bin/python scripts/blend_deviation.py one-sided

`delta`: tests/fixtures/blend/blend.xml with its left sphere's blend made black GGX plastic and
*smooth* gold by 0.5, and the same scene with weight 0 and 1 (the two pure BSDFs): the sphere's
region mean from Mitsuba (llvm_ad_rgb, 4096 spp) and pathlab (`mis`, 8192 spp), and each
renderer's mean of its two pure images (the blend's definition, up to the small second-order
light the sphere sends to itself via the floor).
`one-sided`: the right sphere's blend with a one-sided (not twosided) diffuse beside the rough
glass by 0.3: the sphere's region mean from Mitsuba's llvm_ad_rgb (4 x 4096 spp), its scalar_rgb
(2 x 4096 spp) and pathlab (`mis`, 16384 spp)."""
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
import OpenEXR
import Imath
import mitsuba as mi

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
FIXTURE = os.path.join(ROOT, "tests", "fixtures", "blend", "blend.xml")
PATHLAB = os.environ.get("PATHLAB", os.path.join(ROOT, "target", "release", "pathlab"))
LEFT = (slice(16, 36), slice(8, 26))
RIGHT = (slice(20, 36), slice(36, 52))


def read_exr(path):
    f = OpenEXR.InputFile(path)
    dw = f.header()["dataWindow"]
    w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    pt = Imath.PixelType(Imath.PixelType.FLOAT)
    return np.stack([np.frombuffer(f.channel(c, pt), dtype=np.float32).reshape(h, w) for c in "RGB"], -1).astype(np.float64)


def pathlab(xml, spp, out):
    subprocess.run([PATHLAB, "render", xml, "--method", "mis", "--spp", str(spp), "-o", out], check=True, capture_output=True)
    return read_exr(out)


def mitsuba(xml, variant, spp, passes):
    mi.set_variant(variant)
    scene = mi.load_file(xml)
    return np.mean([np.array(mi.render(scene, spp=spp, seed=k)).astype(np.float64) for k in range(passes)], axis=0)


def main():
    what = sys.argv[1] if len(sys.argv) > 1 else "delta"
    src = open(FIXTURE).read()
    tmp = tempfile.mkdtemp()
    if what == "delta":
        src = src.replace('''            <bsdf type="roughconductor">
                <string name="material" value="Au"/>
                <float name="alpha" value="0.08"/>
            </bsdf>''', '''            <bsdf type="conductor">
                <string name="material" value="Au"/>
            </bsdf>''')
        checker = re.search(r'<texture name="weight" type="checkerboard">.*?</texture>', src, re.S).group(0)
        means = {}
        for w in ["0", "1", "0.5"]:
            xml = os.path.join(tmp, f"w{w}.xml")
            open(xml, "w").write(src.replace(checker, f'<float name="weight" value="{w}"/>'))
            m = mitsuba(xml, "llvm_ad_rgb", 4096, 1)[LEFT].mean()
            p = pathlab(xml, 8192, os.path.join(tmp, f"w{w}.exr"))[LEFT].mean()
            means[w] = (m, p)
        print("delta: Mitsuba blendbsdf %.4f, mean of its pure images %.4f; pathlab %.4f, mean of its pure images %.4f" % (
            means["0.5"][0], (means["0"][0] + means["1"][0]) / 2, means["0.5"][1], (means["0"][1] + means["1"][1]) / 2))
    else:
        src = src.replace('''            <bsdf type="twosided">
                <bsdf type="diffuse">
                    <rgb name="reflectance" value="0.8, 0.2, 0.15"/>
                </bsdf>
            </bsdf>''', '''            <bsdf type="diffuse">
                <rgb name="reflectance" value="0.8, 0.2, 0.15"/>
            </bsdf>''')
        xml = os.path.join(tmp, "one_sided.xml")
        open(xml, "w").write(src)
        llvm = mitsuba(xml, "llvm_ad_rgb", 4096, 4)[RIGHT].mean()
        scalar = mitsuba(xml, "scalar_rgb", 4096, 2)[RIGHT].mean()
        p = pathlab(xml, 16384, os.path.join(tmp, "one_sided.exr"))[RIGHT].mean()
        print("one-sided: Mitsuba llvm_ad_rgb %.5f, scalar_rgb %.5f; pathlab %.5f" % (llvm, scalar, p))


if __name__ == "__main__":
    main()
