#!/usr/bin/env python3
"""Render a scene dumped by `examples/dump_scene.rs` with Mitsuba 3's `path` integrator, as an
independent reference (development only; not used in CI).

usage: python3 tools/mitsuba_ref.py [--variant VARIANT] DUMP_DIR OUT.exr SPP [WIDTH HEIGHT [SEED]]

VARIANT defaults to $MI_VARIANT, else scalar_rgb (e.g. scalar_spectral_polarized,
llvm_ad_spectral_polarized: `tools/polarization_vs_mitsuba.py`).
"""
import json, math, os, sys
import mitsuba as mi

variant = os.environ.get("MI_VARIANT", "scalar_rgb")
if len(sys.argv) > 2 and sys.argv[1] == "--variant":
    variant = sys.argv[2]
    del sys.argv[1:3]
mi.set_variant(variant)
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
    # Both filter the map bilinearly with texel i's centre at u = (i + 1/2)/W, but Mitsuba puts
    # its rows at t = j/(H - 1) (the first and last on the poles) where refract puts them at
    # (j + 1/2)/H, clamped. Resample refract's bilinear function on a grid Mitsuba reads
    # exactly: 7W columns (odd, so refract's texel centres fall on columns) and 8H + 1 rows
    # (refract's centres (j + 1/2)/H = (8j + 4)/8H fall on rows); between grid points both are
    # linear, so Mitsuba reproduces refract's function.
    import numpy as np
    e = s["env_map"]
    px = np.array(mi.Bitmap(os.path.join(d, e["file"])))[..., :3].astype(np.float32)
    H, W = px.shape[:2]
    u = (np.arange(7 * W) + 0.5) / (7 * W)
    t = np.arange(8 * H + 1) / (8 * H)
    x = u * W - 0.5
    i0 = np.floor(x).astype(int)
    fx = (x - i0)[None, :, None]
    y = t * H - 0.5
    j0 = np.floor(y).astype(int)
    fy = (y - j0)[:, None, None]
    c0, c1 = i0 % W, (i0 + 1) % W
    r0, r1 = np.clip(j0, 0, H - 1), np.clip(j0 + 1, 0, H - 1)
    top = px[r0][:, c0] * (1 - fx) + px[r0][:, c1] * fx
    bottom = px[r1][:, c0] * (1 - fx) + px[r1][:, c1] * fx
    mi.Bitmap((top * (1 - fy) + bottom * fy).astype(np.float32)).write(
        os.path.join(d, "env_bilinear.exr"))
    scene["env"] = {"type": "envmap", "filename": os.path.join(d, "env_bilinear.exr"),
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
        if metal == "none" and "polarized" in variant:
            # refract's mirror is the ideal conductor r_s = -1, r_p = 1, which keeps linear
            # polarization; Mitsuba's "none" (eta 0 + 1i) has |r_s| = |r_p| = 1 but a
            # retardance other than 180 degrees off normal incidence. A real eta of 1e6 is
            # the ideal conductor to 1e-6 in both amplitude and phase.
            del b["material"]
            b["eta"], b["k"] = 1e6, 0.0
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
