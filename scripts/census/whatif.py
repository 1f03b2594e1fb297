#!/usr/bin/env python3
"""whatif.py IN OUT FIX... : a probe copy of a scene with chosen blockers patched away, to see what else
pathlab would refuse. FIX: cam (re-orthonormalise the sensor matrix), tex (bitmap/checkerboard -> rgb 0.5),
mask (mask -> its nested bsdf), env (envmap -> constant), eta (clamp negative eta/k to 0), focus (drop focus_distance),
path (drop <path>)."""
import sys, re
import xml.etree.ElementTree as ET
src, dst, *fixes = sys.argv[1:]
tree = ET.parse(src); root = tree.getroot()
def parents(): return {c: p for p in root.iter() for c in p}
if "path" in fixes:
    for e in list(root):
        if e.tag == "path": root.remove(e)
if "focus" in fixes:
    for p in root.iter():
        for c in list(p):
            if c.get("name") == "focus_distance": p.remove(c)
if "cam" in fixes:
    import math
    for s in root.iter("sensor"):
        for m in s.iter("matrix"):
            v = list(map(float, m.get("value").split()))
            col = lambda c: [v[4*r+c] for r in range(3)]
            d = col(2); n = math.sqrt(sum(x*x for x in d)); d = [x/n for x in d]
            u = col(1); k = sum(a*b for a, b in zip(u, d)); u = [a-k*b for a, b in zip(u, d)]; n = math.sqrt(sum(x*x for x in u)); u = [x/n for x in u]
            l0 = col(0); l = [u[1]*d[2]-u[2]*d[1], u[2]*d[0]-u[0]*d[2], u[0]*d[1]-u[1]*d[0]]
            if sum(a*b for a, b in zip(l, l0)) < 0: l = [-x for x in l]
            for r in range(3): v[4*r+0], v[4*r+1], v[4*r+2] = l[r], u[r], d[r]
            m.set("value", " ".join(repr(x) for x in v))
if "tex" in fixes:
    for p in list(root.iter()):
        for i, c in enumerate(list(p)):
            if c.tag == "texture" and c.get("type") in ("bitmap", "checkerboard") and c.get("name"):
                p.remove(c); p.insert(i, ET.Element("rgb", {"name": c.get("name"), "value": "0.5"}))
if "mask" in fixes:
    for p in list(root.iter()):
        for i, c in enumerate(list(p)):
            if c.tag == "bsdf" and c.get("type") == "mask":
                inner = next(x for x in c if x.tag == "bsdf")
                if c.get("id"): inner.set("id", c.get("id"))
                p.remove(c); p.insert(i, inner)
if "env" in fixes:
    for p in list(root.iter()):
        for i, c in enumerate(list(p)):
            if c.tag == "emitter" and c.get("type") == "envmap":
                p.remove(c); e = ET.Element("emitter", {"type": "constant"}); ET.SubElement(e, "rgb", {"name": "radiance", "value": "1"}); p.insert(i, e)
if "eta" in fixes:
    for c in root.iter("rgb"):
        if c.get("name") in ("eta", "k"):
            c.set("value", ", ".join(str(max(0.0, float(x))) for x in re.split(r"[,\s]+", c.get("value").strip())))
tree.write(dst)
