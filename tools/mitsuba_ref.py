#!/usr/bin/env python3
"""Render a scene dumped by `examples/dump_scene.rs` with Mitsuba 3's `path` integrator, as an
independent reference (development only; not used in CI).

usage: python3 tools/mitsuba_ref.py DUMP_DIR OUT.exr SPP [WIDTH HEIGHT [SEED]]
"""
import json, math, os, sys
import mitsuba as mi

mi.set_variant(os.environ.get("MI_VARIANT", "scalar_rgb"))
d, out, spp = sys.argv[1], sys.argv[2], int(sys.argv[3])
s = json.load(open(os.path.join(d, "scene.json")))
st = s["settings"]
w = int(sys.argv[4]) if len(sys.argv) > 4 else st["width"]
h = int(sys.argv[5]) if len(sys.argv) > 5 else st["height"]
seed = int(sys.argv[6]) if len(sys.argv) > 6 else 0
c = s["camera"]
pos, fwd = c["position"], c["forward"]
scene = {
    "type": "scene",
    "integrator": {"type": "path", "max_depth": st["max_depth"], "rr_depth": st["rr_depth"]},
    "sensor": {
        "type": "perspective", "fov_axis": "y", "fov": math.degrees(c["yfov"]),
        "to_world": mi.ScalarTransform4f().look_at(
            origin=pos, target=[pos[i] + fwd[i] for i in range(3)], up=c["up"]),
        "film": {"type": "hdrfilm", "width": w, "height": h, "rfilter": {"type": "box"},
                 "pixel_format": "rgb"},
        "sampler": {"type": "independent", "sample_count": spp},
    },
}
if s.get("env_map"):
    # refract (three.js): u = atan2(z, x)/2π + 1/2; Mitsuba's envmap: u = atan2(x', -z')/2π in
    # its local frame, so local = R_y(-90°) world; refract's rotation turns the map about +Y.
    # Mitsuba filters the map bilinearly, refract reads the nearest texel: repeat every texel
    # 8 × 8 so the bilinear blur shrinks to an eighth of a texel.
    import numpy as np
    e = s["env_map"]
    px = np.array(mi.Bitmap(os.path.join(d, e["file"])))[..., :3].astype(np.float32)
    px = np.repeat(np.repeat(px, 8, axis=0), 8, axis=1)
    mi.Bitmap(px).write(os.path.join(d, "env_x8.exr"))
    scene["env"] = {"type": "envmap", "filename": os.path.join(d, "env_x8.exr"),
                    "scale": e["strength"],
                    "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], e["rotation"] + 90.0)}
elif max(s["environment"]) > 0:
    scene["env"] = {"type": "constant", "radiance": {"type": "rgb", "value": s["environment"]}}
for i, m in enumerate(s["materials"]):
    rgb = lambda v: {"type": "rgb", "value": v}
    k = m["kind"]
    # Tabulated metal (extras.conductor): Mitsuba's own Au/Ag/Cu/Al data, which refract ships
    # too; the base colour is the specular_reflectance tint in both. "none" = eta 0, k 1: a
    # perfect mirror (refract's constant reflectance = base colour).
    metal = m.get("conductor") or "none"
    if k == "diffuse":
        b = {"type": "diffuse", "reflectance": rgb(m["base_color"])}
    elif k == "mirror":
        b = {"type": "conductor", "material": metal, "specular_reflectance": rgb(m["base_color"])}
    elif k == "glossy":
        b = {"type": "roughconductor", "material": metal, "alpha": m["roughness"] ** 2,
             "distribution": m["distribution"], "specular_reflectance": rgb(m["base_color"])}
    elif k == "glass" and m["ior"] == m.get("ext_ior", 1.0):
        # Index-matched: Mitsuba refuses a dielectric with equal IORs; it passes light
        # straight through, exactly what the null BSDF does.
        b = {"type": "null"}
    elif k == "glass":
        if m["roughness"] > 0.0316:
            b = {"type": "roughdielectric", "int_ior": m["ior"], "ext_ior": m.get("ext_ior", 1.0),
                 "alpha": m["roughness"] ** 2, "distribution": m["distribution"]}
        else:
            b = {"type": "dielectric", "int_ior": m["ior"], "ext_ior": m.get("ext_ior", 1.0)}
    elif k == "thin":
        b = {"type": "thindielectric", "int_ior": m["ior"], "ext_ior": 1.0}
    if m["double_sided"] and k in ("diffuse", "mirror", "glossy"):
        b = {"type": "twosided", "bsdf": b}
    shape = {"type": "obj", "filename": os.path.join(d, m["file"]), "bsdf": b,
             "face_normals": False}
    if max(m["emission"]) > 0:
        shape["emitter"] = {"type": "area", "radiance": rgb(m["emission"])}
        shape["bsdf"] = {"type": "diffuse", "reflectance": rgb([0, 0, 0])}
        if m["double_sided"]:
            print("warning: Mitsuba area lights are one-sided; double-sided emission differs")
    scene[f"shape{i}"] = shape
if __name__ == "__main__":  # `tools/mitsuba_rays.py` imports the scene dict instead
    img = mi.render(mi.load_dict(scene), seed=seed)
    mi.Bitmap(img).write(out)
    print("wrote", out)
