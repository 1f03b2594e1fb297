#!/usr/bin/env python3
"""pathvariant.py FILE_WITH_INTEGRATOR OUT_FILE : replace the (uncommented, outermost) <integrator> element by
<integrator type="path"> keeping a max_depth child (the innermost one) if present."""
import sys, re
src, dst = sys.argv[1:3]
t = open(src).read()
# mask comments so commented-out integrators are not touched
masked = re.sub(r"<!--.*?-->", lambda m: " "*len(m.group(0)), t, flags=re.S)
m = re.search(r"<integrator\b[^>]*?/>|<integrator\b[^>]*>", masked)
start = m.start()
if m.group(0).endswith("/>"):
    end = m.end()
else:
    depth = 0; pos = start
    for tok in re.finditer(r"<integrator\b[^>]*?/>|<integrator\b[^>]*>|</integrator\s*>", masked[start:]):
        s = tok.group(0)
        if s.startswith("</"): depth -= 1
        elif not s.endswith("/>"): depth += 1
        if depth == 0: end = start + tok.end(); break
old = t[start:end]
md = re.findall(r'<integer\s+name=["\']max_depth["\']\s+value=["\']([^"\']+)["\']\s*/>', old)
rr = re.findall(r'<integer\s+name=["\']rr_depth["\']\s+value=["\']([^"\']+)["\']\s*/>', old)
new = '<integrator type="path">' + (f'<integer name="max_depth" value="{md[-1]}"/>' if md else '') + (f'<integer name="rr_depth" value="{rr[-1]}"/>' if rr else '') + '</integrator>'
open(dst, "w").write(t[:start] + new + t[end:])
print(f"{src}: {' '.join(old.split())[:160]}  ->  {new}")
