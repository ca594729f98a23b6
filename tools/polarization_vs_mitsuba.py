#!/usr/bin/env python3
"""Polarized against unpolarized intensity, refract against Mitsuba 3 (issue 38; development
only, not run in CI; docs/polarization.md, "Checked against Mitsuba 3").

Without a filter a polarized render's intensity differs from the unpolarized one only where a
path meets several polarizing events (here: the two or more refractions and reflections through
a smooth glass sphere). For each seed this renders the scene four times at the same spp —
refract unpolarized and `--polarized` (CPU), Mitsuba 3 `<prefix>_spectral` and
`<prefix>_spectral_polarized` (`tools/mitsuba_ref.py` on the scene dumped by
`examples/dump_scene.rs`) — and compares the relative difference (P − U) / U of the two
renderers over the pixels that see the glass (the mask: camera rays that hit the bounding sphere
of a glass material's mesh), in total and per block of pixels, with the spread over seeds as the
noise estimate.

usage: python3 tools/polarization_vs_mitsuba.py [--scene builtin:cornell-glass|periscope|FILE] [--size 128]
           [--spp 64] [--seeds 4] [--block 16] [--prefix llvm_ad|scalar] [--work /tmp/polmi]
Needs `cargo build --release --bin refract --example dump_scene` first. The llvm_ad variants
need LLVM ≥ 15 (LLVM 14 aborts in instruction selection): `apt-get install libllvm19` and
DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1.
"""
import argparse, json, math, os, subprocess, sys
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.dirname(here)
ap = argparse.ArgumentParser()
ap.add_argument("--scene", default="builtin:cornell-glass")
ap.add_argument("--size", type=int, default=128)
ap.add_argument("--spp", type=int, default=64)
ap.add_argument("--seeds", type=int, default=4)
ap.add_argument("--block", type=int, default=16)
ap.add_argument("--prefix", default="llvm_ad", help="Mitsuba variant prefix: scalar or llvm_ad")
ap.add_argument("--work", default="/tmp/polmi")
ap.add_argument("--threads", type=int, default=2)
ap.add_argument("--reuse", action="store_true",
                help="read the EXRs an earlier run left in --work instead of rendering them again")
a = ap.parse_args()
os.makedirs(a.work, exist_ok=True)


def periscope(path):
    """A Brewster periscope (glTF; not a built-in): the camera sees a level smooth glass plate
    (n = 1.5, 4 cm thick) at Brewster's angle θB = atan 1.5 in the image's centre; the reflected
    ray meets a second plate, also at θB, whose plane of incidence is crossed with the first's,
    and goes on to a square emitter (radiance 5). The first reflection passes only s light,
    which is p for the second: polarized, the centre is dark (r_p = 0), unpolarized it is
    F(θB)² of the emitter. Black surroundings."""
    th = math.atan(1.5)
    ct, st = math.cos(th), math.sin(th)
    ex = np.array([1.0, 0, 0])
    d1 = np.array([0, ct, -st])
    nb = -ct * d1 + st * ex
    d2 = d1 + 2 * ct * nb
    pb = 1.2 * d1
    pe = pb + 1.2 * d2
    eye = 2.6 * np.array([0, ct, st])
    pos, nor, idx = [], [], []

    def quad(c, n, u, half_u, half_v):  # counter-clockwise seen from n
        v = np.cross(n, u)
        base = len(pos)
        for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            pos.append(c + su * half_u * u + sv * half_v * v)
            nor.append(n)
        idx.extend([base, base + 1, base + 2, base, base + 2, base + 3])

    def slab(c, n, u, half, thick):  # a closed box: faces ±n, ±u, ±v
        v = np.cross(n, u)
        for ax, hw in ((n, thick / 2), (u, half), (v, half)):
            o1, o2 = [w for w in (n, u, v) if w is not ax]
            h1 = thick / 2 if o1 is n else half
            h2 = thick / 2 if o2 is n else half
            for sgn in (1, -1):
                nn = sgn * ax
                uu = o1 if np.dot(np.cross(nn, o1), o2) > 0 else o2
                hu, hv = (h1, h2) if uu is o1 else (h2, h1)
                quad(c + hw * nn, nn, uu, hu, hv)

    ranges = []
    for f in (lambda: slab(np.array([0, -0.02, 0]), np.array([0, 1.0, 0]), ex, 0.6, 0.04),
              lambda: slab(pb - 0.02 * nb, nb, ex - np.dot(ex, nb) * nb, 1.0, 0.04),
              lambda: quad(pe, -d2, np.cross(-d2, ex) / np.linalg.norm(np.cross(-d2, ex)),
                           1.5, 1.5)):
        i0 = len(idx)
        f()
        ranges.append((i0, len(idx) - i0))
    P = np.array(pos, np.float32)
    N = np.array(nor, np.float32)
    I = np.array(idx, np.uint32)
    blob = P.tobytes() + N.tobytes() + I.tobytes()
    import base64
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": P.nbytes},
             {"buffer": 0, "byteOffset": P.nbytes, "byteLength": N.nbytes},
             {"buffer": 0, "byteOffset": P.nbytes + N.nbytes, "byteLength": I.nbytes}]
    acc = [{"bufferView": 0, "componentType": 5126, "count": len(P), "type": "VEC3",
            "min": P.min(0).tolist(), "max": P.max(0).tolist()},
           {"bufferView": 1, "componentType": 5126, "count": len(N), "type": "VEC3"}]
    for i0, n in ranges:
        acc.append({"bufferView": 2, "byteOffset": 4 * i0, "componentType": 5125, "count": n,
                    "type": "SCALAR"})
    glass = {"name": "glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1],
             "metallicFactor": 0.0, "roughnessFactor": 0.0},
             "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                            "KHR_materials_ior": {"ior": 1.5},
                            "KHR_materials_volume": {"thicknessFactor": 0.04}}}
    light = {"name": "panel", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]},
             "emissiveFactor": [1, 1, 1],
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 5.0}}}
    fwd = -eye / np.linalg.norm(eye)
    right = np.cross(fwd, [0, 1, 0])
    right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    R = np.stack([right, up, -fwd], 1)  # camera looks along its -Z
    w = math.sqrt(max(0, 1 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    q = [(R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w),
         (R[1, 0] - R[0, 1]) / (4 * w), w]
    prims = [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2 + k, "material": m}
             for k, m in enumerate((0, 0, 1))]
    g = {"asset": {"version": "2.0"},
         "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_ior",
                            "KHR_materials_volume", "KHR_materials_emissive_strength"],
         "scene": 0,
         "scenes": [{"nodes": [0, 1], "extras": {"environment": [0, 0, 0],
                                                 "render": {"max_depth": 16}}}],
         "nodes": [{"mesh": 0}, {"camera": 0, "translation": eye.tolist(), "rotation": q}],
         "cameras": [{"type": "perspective", "perspective": {"yfov": 0.3, "aspectRatio": 1.0,
                                                            "znear": 0.01}}],
         "meshes": [{"primitives": prims}], "materials": [glass, light],
         "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64,"
                      + base64.b64encode(blob).decode()}],
         "bufferViews": views, "accessors": acc}
    json.dump(g, open(path, "w"))


if a.scene == "periscope":
    a.scene = os.path.join(a.work, "periscope.gltf")
    periscope(a.scene)
dump = os.path.join(a.work, "dump")
exe = os.path.join(root, "target", "release")
subprocess.run([os.path.join(exe, "examples", "dump_scene"), a.scene, dump], check=True)
W = H = a.size


def read_exr(path):
    import mitsuba as mi
    if mi.variant() is None:
        mi.set_variant("scalar_rgb")
    return np.array(mi.Bitmap(path))[..., :3].astype(np.float64)


def render_refract(pol, seed):
    out = os.path.join(a.work, f"refract_{'pol' if pol else 'unp'}_{seed}.exr")
    cmd = [os.path.join(exe, "refract"), "render", "--scene", a.scene, "--device", "cpu",
           "--estimator", "path", "--spp", str(a.spp), "--width", str(W), "--height", str(H),
           "--seed", str(seed), "--threads", str(a.threads), "--out", out]
    if pol:
        cmd.append("--polarized")
    if a.reuse and os.path.exists(out):
        return read_exr(out)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return read_exr(out)


def render_mitsuba(pol, seed):
    variant = f"{a.prefix}_spectral" + ("_polarized" if pol else "")
    out = os.path.join(a.work, f"mitsuba_{variant}_{seed}.exr")
    if a.reuse and os.path.exists(out):
        return read_exr(out)
    subprocess.run([sys.executable, os.path.join(here, "mitsuba_ref.py"), "--variant", variant,
                    dump, out, str(a.spp), str(W), str(H), str(seed)], check=True,
                   stdout=subprocess.DEVNULL)
    return read_exr(out)


# The mask: pixels whose camera ray (through the pixel centre) hits the bounding sphere of a
# glass material's mesh.
s = json.load(open(os.path.join(dump, "scene.json")))
c = s["camera"]
pos, fwd, up = (np.array(c[k], float) for k in ("position", "forward", "up"))
fwd /= np.linalg.norm(fwd)
right = np.cross(fwd, up)
right /= np.linalg.norm(right)
up = np.cross(right, fwd)
t = math.tan(c["yfov"] / 2)
ys, xs = np.mgrid[0:H, 0:W]
px = ((xs + 0.5) / W * 2 - 1) * t * W / H
py = (1 - (ys + 0.5) / H * 2) * t
d = fwd + px[..., None] * right + py[..., None] * up
d /= np.linalg.norm(d, axis=-1, keepdims=True)
mask = np.zeros((H, W), bool)
for m in s["materials"]:
    if m["kind"] != "glass":
        continue
    v = np.array([list(map(float, l.split()[1:4])) for l in open(os.path.join(dump, m["file"]))
                  if l.startswith("v ")])
    lo, hi = v.min(0), v.max(0)
    cen, rad = (lo + hi) / 2, (hi - lo).max() / 2
    oc = pos - cen
    b = d @ oc
    mask |= b * b - (oc @ oc - rad * rad) > 0
print(f"scene {a.scene}, {W}x{H}, {a.spp} spp, {a.seeds} seeds, mask {mask.sum()} pixels")

nb = W // a.block
res = {}
for name, fn in (("refract", render_refract), ("mitsuba", render_mitsuba)):
    tot, blocks, level = [], [], []
    for seed in range(a.seeds):
        u, p = fn(False, seed).sum(-1), fn(True, seed).sum(-1)
        level.append(u[mask].mean())
        tot.append((p[mask].sum() - u[mask].sum()) / u[mask].sum())
        bu = (u * mask).reshape(nb, a.block, nb, a.block).sum((1, 3))
        bp = (p * mask).reshape(nb, a.block, nb, a.block).sum((1, 3))
        blocks.append((bp - bu) / np.where(bu > 0, bu, np.nan))
    tot, blocks = np.array(tot), np.array(blocks)
    res[name] = (tot.mean(), tot.std(ddof=1) / math.sqrt(a.seeds),
                 np.nanmean(blocks, 0), np.nanstd(blocks, 0, ddof=1) / math.sqrt(a.seeds))
    print(f"{name}: (P - U)/U over the mask = {100 * res[name][0]:+.3f} % "
          f"± {100 * res[name][1]:.3f} % (standard error over seeds); unpolarized mean "
          f"R+G+B over the mask {np.mean(level):.5g} ± {np.std(level, ddof=1) / math.sqrt(a.seeds):.2g}")
(rt, re, rb, rbe), (mt, me, mb, mbe) = res["refract"], res["mitsuba"]
print(f"difference refract - mitsuba: {100 * (rt - mt):+.3f} % ± {100 * math.hypot(re, me):.3f} %"
      f" (z = {(rt - mt) / math.hypot(re, me):.2f})")
# Blocks with enough glass in them to matter: at least a quarter of their pixels in the mask.
full = mask.reshape(nb, a.block, nb, a.block).mean((1, 3)) >= 0.25
full &= np.isfinite(rb) & np.isfinite(mb)
z = ((rb - mb) / np.hypot(rbe, mbe))[full]
print(f"{full.sum()} blocks of {a.block}x{a.block} (>= 25 % glass): refract (P-U)/U from "
      f"{100 * np.nanmin(rb[full]):+.2f} to {100 * np.nanmax(rb[full]):+.2f} %, mitsuba from "
      f"{100 * np.nanmin(mb[full]):+.2f} to {100 * np.nanmax(mb[full]):+.2f} %")
print(f"per-block z (refract - mitsuba): rms {np.sqrt(np.nanmean(z * z)):.2f}, max |z| "
      f"{np.nanmax(np.abs(z)):.2f}; chi2/dof {np.nanmean(z * z):.2f}")
for i, j in zip(*np.nonzero(full)):
    print(f"  block ({i},{j}): refract {100 * rb[i, j]:+.2f} ± {100 * rbe[i, j]:.2f} %, "
          f"mitsuba {100 * mb[i, j]:+.2f} ± {100 * mbe[i, j]:.2f} %")
