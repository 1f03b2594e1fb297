"""The regions of assets/scenes/veach_mis_regions.toml: each plate's highlight of each light of
assets/scenes/veach_mis.xml at 128x72, as 7x3-pixel rectangles around the point of the plate's top
face that mirrors the light's centre into the camera (clamped onto the face where that point
falls off it). Geometry copied from the XML; needs numpy.

    python3 scripts/veach_regions.py > assets/scenes/veach_mis_regions.toml
"""
import numpy as np
W, H = 128, 72
cam = np.array([28.2792, 3.5, 1.23612e-6]); fwd = np.array([-1.0, 0, -4.37113e-08]); up = np.array([0, 1.0, 0]); left = np.array([-4.37113e-08, 0, 1.0])
t = np.tan(np.radians(17.5))
plates = {
 'smooth': "0.805757 0.0961775 0 0.264069 -0.673242 0.115108 0 4.09801 0 0 4 0 0 0 0 1",
 'glossy': "0.972057 0.0567134 0 3.06163 -0.396994 0.138865 0 2.71702 0 0 4 0 0 0 0 1",
 'rough': "1.03191 0.0277252 0 7.09981 -0.194077 0.147415 0 1.81891 0 0 4 0 0 0 0 1",
 'super-rough': "1.04217 0.0182831 0 10.6769 -0.127982 0.148882 0 1.23376 0 0 4 0 0 0 0 1",
}
lights = {'large': (np.array([0, 6.5, -2.8]), 1.0), 'medium': (np.array([0, 6.5, 0.0]), 0.5), 'small': (np.array([0, 6.5, 2.7]), 0.05)}
def project(p):
    d = p - cam; d = d / np.dot(d, fwd)
    sx = np.dot(d, -left) / t; sy = np.dot(d, up) / (t * H / W)
    return (sx + 1) * W / 2, (1 - sy) * H / 2
out = ['# Veach scene regions: each plate highlight of each light, at the 128x72 fixture size', '# (projected from the plate and light positions in assets/scenes/veach_mis.xml by scripts/veach_regions.py).', 'size = [128, 72]', '']
for pn, ms in plates.items():
    M = np.array([float(v) for v in ms.split()]).reshape(4, 4)
    top = M @ np.array([0, 1, 0, 1.0]); n = np.linalg.inv(M[:3,:3]).T @ np.array([0, 1.0, 0]); n /= np.linalg.norm(n)
    for ln, (c, r) in lights.items():
        cm = c - 2 * np.dot(c - top[:3], n) * n
        d = cm - cam; tt = np.dot(top[:3] - cam, n) / np.dot(d, n); p = cam + tt * d
        loc = np.linalg.solve(M[:3,:3], p - M[:3,3])
        # clamp onto the top face (the highlight's centre where the mirror point falls off it)
        loc = np.clip(loc, -1, 1); loc[1] = 1
        q = M[:3,:3] @ loc + M[:3,3]
        x, y = project(q)
        hw, hh = 3, 1
        out += ['[[region]]', f'name = "{pn} plate, {ln} light"', f'x = {int(x) - hw}', f'y = {int(y) - hh}', f'width = {2 * hw + 1}', f'height = {2 * hh + 1}', '']
print('\n'.join(out))
