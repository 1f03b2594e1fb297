#!/usr/bin/env python3
"""plugins.py SCENE.xml -> JSON: every plugin used (includes resolved, $defaults substituted) and
the unsupported features judged against pathlab's current list (brief of the census)."""
import sys, os, re, json
import xml.etree.ElementTree as ET
scene = sys.argv[1]
defaults = {}
items = []   # (kind, type, context-string)
feats = set()  # unsupported features
notable = []
def subst(v): return re.sub(r"\$(\w+)", lambda m: defaults.get(m.group(1), m.group(0)), v) if v else v
def load(path, top):
    root = ET.parse(path).getroot()
    for el in root:
        if el.tag == "default": defaults.setdefault(el.get("name"), el.get("value"))
    out = []
    for el in root:
        if el.tag == "include":
            fn = subst(el.get("filename"))
            for d in (os.path.dirname(path), os.path.dirname(top)):
                p = os.path.join(d, fn)
                if os.path.exists(p): out += load(p, top); break
            else: notable.append(f"include {fn} not found")
        else: out.append(el)
    return out
SUP_BSDF = {"diffuse","conductor","roughconductor","dielectric","thindielectric","roughdielectric","plastic","roughplastic","twosided","modphong"}
SUP_EMIT = {"area","constant"}
SUP_SHAPE = {"obj","ply","rectangle","cube","sphere"}
PLUGIN_TAGS = {"bsdf","texture","emitter","shape","sensor","integrator","medium","phase","film","sampler","rfilter","volume","spectrum"}
ids = {}
def walk(el, ctx):
    tag = el.tag; typ = subst(el.get("type"))
    name = el.get("name")
    if el.get("id"): ids[el.get("id")] = (tag, typ)
    here = ctx
    if tag in ("bsdf","texture","emitter","shape","sensor","integrator","medium","phase","volume"):
        label = f"{tag}:{typ}" + (f"[{name}]" if name else "")
        items.append((tag, typ, "/".join(ctx + [label])))
        here = ctx + [label]
        parent = ctx[-1] if ctx else ""
        if tag == "bsdf":
            if typ not in SUP_BSDF: feats.add(f"bsdf {typ}")
            if typ == "twosided":
                n = sum(1 for c in el if c.tag == "bsdf" or (c.tag=="ref"))
                if n > 1: feats.add("twosided with 2 bsdfs")
            if typ in ("conductor","roughconductor"):
                for c in el:
                    if c.get("name") == "material" and subst(c.get("value")) != "none":
                        feats.add(f"named conductor material"); notable.append(f"{typ} material={subst(c.get('value'))}")
            for c in el:
                if c.get("name") in ("alpha_u","alpha_v"):
                    feats.add("alpha_u/alpha_v (anisotropic)")
        elif tag == "texture":
            feats.add(f"texture {typ}")
            notable.append(f"texture {typ} as `{name}` in {parent}")
        elif tag == "emitter":
            if typ not in SUP_EMIT: feats.add(f"emitter {typ}")
        elif tag == "shape":
            if typ not in SUP_SHAPE: feats.add(f"shape {typ}")
        elif tag == "sensor":
            if typ != "perspective": feats.add(f"sensor {typ}")
            for c in el:
                n = c.get("name")
                if n in ("focal_length","focus_distance","principal_point_offset_x","principal_point_offset_y","aperture_radius"):
                    feats.add(f"sensor {n}"); notable.append(f"sensor {n}={c.get('value')}")
            for c in el:
                if c.tag == "film":
                    for cc in c:
                        if cc.get("name") in ("crop_width","crop_height","crop_offset_x","crop_offset_y"): feats.add("film crop")
        elif tag == "integrator":
            if typ not in ("path","volpath","volpathmis"): feats.add(f"integrator {typ}")
            for c in el:
                if c.get("name") == "hide_emitters" and subst(c.get("value")) == "true": feats.add("hide_emitters")
        elif tag in ("medium","phase","volume"):
            feats.add(f"{tag} {typ}")
    elif tag == "spectrum":
        v = subst(el.get("value") or "")
        if ":" in v or el.get("filename") or any(c.get("name")=="filename" for c in el) or typ:
            feats.add("spectrum by wavelengths/file"); items.append(("spectrum","wavelengths","/".join(ctx+[f"spectrum[{el.get('name')}]"])))
        else:
            items.append(("spectrum","constant","/".join(ctx+[f"spectrum[{el.get('name')}]"])))
    elif tag == "rgb":
        items.append(("rgb", el.get("name"), "/".join(ctx)))
    elif tag == "ref":
        rid = el.get("id")
        if rid in ids and ids[rid][0] == "texture":
            feats.add(f"texture {ids[rid][1]}"); notable.append(f"<ref> to texture {rid} as `{el.get('name')}`")
        if rid in ids and ids[rid][0] == "medium": feats.add(f"medium {ids[rid][1]}")
    for c in el: walk(c, here)
top = load(scene, scene)
for el in top: walk(el, [])
count = {}
for k,t,_ in items:
    if k in ("rgb",): continue
    key = f"{k}:{t}"; count[key] = count.get(key,0)+1
nested = sorted({c for k,t,c in items if k=="bsdf" and c.count("bsdf:")>1})
print(json.dumps({"scene": scene, "plugins": count, "rgb_params": sorted({t for k,t,_ in items if k=="rgb"}),
    "nested_bsdfs": nested[:12], "unsupported": sorted(feats), "notable": sorted(set(notable))}, indent=1))
