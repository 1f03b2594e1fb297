# per-file blockers (from pathlab check of the file / its .path variant, cross-checked with plugins/*.json)
F = {
 "md/scenes/cbox/cbox.xml": ["focus_distance", "wavelength spectrum"],
 "md/scenes/cbox/cbox-rgb.xml": ["focus_distance", "top-level emitter via <ref>"],
 "md/scenes/matpreview/matpreview.xml": ["focus_distance", "envmap", "checkerboard", "serialized"],
 "md/scenes/hello.xml": ["<path> element", "no fov (focal-length default)", "point"],
 "md/docs/scenes/bsdf_roughplastic_ggx.xml": ["<path> element", "focus_distance", "envmap", "checkerboard", "serialized"],
 "md/docs/scenes/bsdf_conductor_aluminium.xml": ["<path> element", "focus_distance", "envmap", "checkerboard", "serialized", "named conductor"],
 "md/docs/scenes/bsdf_twosided_cbox.xml": ["<path> element", "focus_distance", "wavelength spectrum"],
 "md/docs/scenes/texture_checkerboard.xml": ["<path> element", "focus_distance", "envmap", "checkerboard", "serialized"],
 "md/docs/scenes/shape_ply_bunny.xml": ["<path> element", "focus_distance", "envmap", "checkerboard", "serialized"],
 "md/docs/scenes/integrator_direct_both.xml": ["<path> element", "include-relative mesh paths"],
 "md/tests/.../test_roughdielectric_path.xml": ["<path> element", "no fov (focal-length default)", "wavelength spectrum", "envmap", "point"],
 "md/tests/.../test_various_shapes_path.xml": ["no fov (focal-length default)", "checkerboard", "cylinder", "disk", "serialized", "sdfgrid", "shapegroup/instance"],
 "md/tests/infinite_mirrors/scene_path.xml": ["<path> element", "no fov (focal-length default)", "envmap"],
 "tut/scenes/cbox.xml": ["focus_distance"],
 "tut/scenes/simple.xml": ["no fov (focal-length default)", "point"],
 "tut/scenes/lego/scene.xml": ["hide_emitters", "envmap", "volume texture"],
 "tut/scenes/shadow_art.xml": ["bsplinecurve"],
 "ppg/cornell-box/scene.xml": [],
 "ppg/veach-ajar/scene.xml": ["camera to_world tolerance", "bitmap", "checkerboard", "ASSETS"],
 "ppg/veach-bidir/scene.xml": ["camera to_world tolerance"],
 "ppg/veach-mis/scene.xml": [],
 "ppg/teapot/scene_v3.xml": ["camera to_world tolerance", "checkerboard", "envmap", "ASSETS"],
 "ppg/torus/scene.xml": ["focus_distance", "named conductor", "serialized", "directional"],
 "restir/staircase2/scene.xml": ["bitmap", "principled", "medium", "disk"],
 "restir/living-room-2/scene.xml": ["bitmap", "mask", "negative eta/k", "ASSETS"],
 "restir/dining_hall_chalice/scene.xml": ["bitmap", "envmap", "ASSETS"],
 "restir/cornell_box_picture/scene_picture.xml": ["bitmap"],
}
from collections import Counter
c = Counter(x for v in F.values() for x in v)
for k, n in c.most_common(): print(f"{n:3d}  {k}  (sole blocker of {sum(1 for v in F.values() if v == [k])})")
def loads(added, assets=False):
    return [f for f, v in F.items() if all(x in added or (assets and x == "ASSETS") for x in v)]
print("now:", loads(set()))
print("+roughplastic+named:", loads({"named conductor"}))
print("+textures:", loads({"named conductor", "bitmap", "checkerboard"}))
cheap = {"focus_distance", "<path> element", "include-relative mesh paths", "camera to_world tolerance", "no fov (focal-length default)", "top-level emitter via <ref>", "negative eta/k", "hide_emitters"}
print("+cheap parser fixes:", loads(cheap))
print("+cheap+textures:", loads(cheap | {"named conductor", "bitmap", "checkerboard"}), "| with assets:", loads(cheap | {"named conductor", "bitmap", "checkerboard"}, True))
print("+cheap+textures+envmap+serialized:", loads(cheap | {"named conductor", "bitmap", "checkerboard", "envmap", "serialized"}, True))
print("+ ... + wavelength + point:", loads(cheap | {"named conductor", "bitmap", "checkerboard", "envmap", "serialized", "wavelength spectrum", "point", "mask"}, True))
