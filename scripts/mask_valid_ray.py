#!/usr/bin/env python3
"""Mitsuba 3.9.1's `path` against its own `direct` and pathlab on a masked panel with nothing
behind it (the README's "Scenes from Mitsuba", mask row): tests/fixtures/twosided/twosided.xml
without its back wall, at max_depth 2 (direct light only), 48x48. Prints each renderer's mean
of the masked panel's pixels (rows 19-21, columns 36-38) with the mask and without it.

Usage: /tmp/mitsuba-venv/bin/python scripts/mask_valid_ray.py [path/to/pathlab]"""
import os, subprocess, sys, tempfile
import numpy as np
import mitsuba as mi

mi.set_variant('llvm_ad_rgb')
root = os.path.join(os.path.dirname(__file__), '..')
pathlab = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, 'target/release/pathlab')
src = open(os.path.join(root, 'tests/fixtures/twosided/twosided.xml')).read()
wall = src.index('    <!-- A wall behind everything')
src = src[:wall] + src[src.index('    <!-- Front to the camera'):]
src = src.replace('<integer name="max_depth" value="6"/>', '<integer name="max_depth" value="2"/>')
mask_open = '<bsdf type="mask">\n            <float name="opacity" value="0.5"/>\n'
unmasked = src.replace(mask_open, '').replace('            </bsdf>\n        </bsdf>\n    </shape>\n</scene>', '            </bsdf>\n    </shape>\n</scene>')
direct = '<integrator type="direct"><integer name="emitter_samples" value="1"/><integer name="bsdf_samples" value="1"/>'
tmp = tempfile.mkdtemp()
for label, text in [('masked', src), ('unmasked', unmasked)]:
    f = os.path.join(tmp, label + '.xml')
    open(f, 'w').write(text)
    for integrator, t in [('path', text), ('direct', text.replace('<integrator type="path">', direct).replace('<integer name="max_depth" value="2"/>', ''))]:
        g = os.path.join(tmp, f'{label}_{integrator}.xml')
        open(g, 'w').write(t)
        img = np.array(mi.render(mi.load_file(g, resx=48, resy=48), spp=8192))
        print(f'mitsuba {integrator:6s} {label:8s}', img[19:22, 36:39].mean((0, 1)))
    out = os.path.join(tmp, label + '.exr')
    subprocess.run([pathlab, 'render', f, '--method', 'mis', '--spp', '8192', '-q', '-o', out], check=True)
    img = np.array(mi.Bitmap(out))[:, :, :3]
    print(f'pathlab mis    {label:8s}', img[19:22, 36:39].mean((0, 1)))
