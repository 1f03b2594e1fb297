#!/usr/bin/env python3
"""extract.py MIRROR_DIR REPO_LABEL SCENE_PATH : copy scene + includes + referenced files into /tmp/census/<label>/..."""
import sys, os, subprocess, re, posixpath
import xml.etree.ElementTree as ET
mirror, label, scene = sys.argv[1:4]
OUT = f"/tmp/census/{label}"
notes = []
def blob_size(path):
    r = subprocess.run(["git","-C",mirror,"cat-file","-s",f"HEAD:{path}"],capture_output=True,text=True)
    return int(r.stdout) if r.returncode==0 else None
def get(path):
    return subprocess.run(["git","-C",mirror,"show",f"HEAD:{path}"],capture_output=True).stdout
done=set()
def copy(path):
    if path in done: return True
    done.add(path)
    sz = blob_size(path)
    if sz is None:
        notes.append(f"MISSING {path}"); return False
    if sz > 50e6:
        notes.append(f"TOO-BIG {path} ({sz} B)"); return False
    data = get(path)
    if data.startswith(b"version https://git-lfs"):
        notes.append(f"LFS-POINTER {path}"); return False
    dst = os.path.join(OUT, path); os.makedirs(os.path.dirname(dst), exist_ok=True)
    if os.path.exists(dst): os.chmod(dst,0o644)
    open(dst,"wb").write(data)
    return True
def copy_to(src, dst_rel):
    sz = blob_size(src)
    if sz > 50e6: notes.append(f"TOO-BIG {src} ({sz} B)"); return False
    data = get(src)
    if data.startswith(b"version https://git-lfs"): notes.append(f"LFS-POINTER {src}"); return False
    dst = os.path.join(OUT, dst_rel); os.makedirs(os.path.dirname(dst), exist_ok=True)
    open(dst,"wb").write(data); done.add(dst_rel); return True
def process_xml(path, defaults):
    if not copy(path): return
    try:
        root = ET.fromstring(get(path))
    except Exception as e:
        notes.append(f"XML-PARSE-ERROR {path}: {e}"); return
    base = posixpath.dirname(path)
    for el in root.iter():
        if el.tag == "default": defaults.setdefault(el.get("name"), el.get("value"))
    def subst(v): return re.sub(r"\$(\w+)", lambda m: defaults.get(m.group(1), m.group(0)), v)
    for el in root.iter():
        fn = None
        if el.tag == "include": fn = el.get("filename")
        elif el.get("name") == "filename" and el.get("value") is not None: fn = el.get("value")
        if fn is None: continue
        fn = subst(fn)
        # resolve relative to the scene's (top-level) directory, as Mitsuba does (file resolver gets scene dir)
        cands = [posixpath.normpath(posixpath.join(topdir, fn)), posixpath.normpath(posixpath.join(base, fn))]
        ok=False
        for c in cands:
            if blob_size(c) is not None:
                if el.tag == "include": process_xml(c, defaults)
                else: copy(c)
                ok=True; break
        if not ok and blob_size("common/"+fn) is not None:
            # Mitsuba's test/doc harness adds common/ to the file resolver: place copies where a
            # scene-relative or include-relative lookup finds them
            for c in dict.fromkeys(cands):
                if copy_to("common/"+fn, c): ok=True
            if ok: notes.append(f"FROM-COMMON {fn}")
        if not ok: notes.append(f"MISSING {fn} (from {path})")
topdir = posixpath.dirname(scene)
process_xml(scene, {})
for n in sorted(set(notes)): print(n)
print(f"copied {len(done)} files")
