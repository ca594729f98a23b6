#!/usr/bin/env python3
"""Mitsuba 3's own ray-cast throughput on a scene dumped by `examples/dump_scene.rs`: the rays of
`refract bench --quick` (10^6 rays from uniform points in the middle 80 % of the bounds, uniform
directions) through `ray_intersect_preliminary` (traversal only), `ray_intersect` (with the
surface interaction) and `ray_test` (shadow rays); the median of 7 runs each. Development
only (docs/accuracy.md, "Against Mitsuba"); use `MI_VARIANT=llvm_ad_rgb` for the vectorised backend.

usage: python3 tools/mitsuba_rays.py DUMP_DIR
"""
import os, sys, time

sys.argv = [sys.argv[0], sys.argv[1], os.devnull, "1"]
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mitsuba_ref  # noqa: E402  (builds the scene dict from the dump)
import drjit as dr  # noqa: E402
mi = mitsuba_ref.mi

N = 1_000_000
sc = mi.load_dict(mitsuba_ref.scene)
lo, hi = sc.bbox().min, sc.bbox().max
rng = mi.PCG32(size=N)
u = lambda: rng.next_float32()  # noqa: E731
o = mi.Point3f(*[lo[i] + (hi[i] - lo[i]) * (0.1 + 0.8 * u()) for i in range(3)])
d = mi.warp.square_to_uniform_sphere(mi.Point2f(u(), u()))
dr.eval(o, d)
ray = mi.Ray3f(o, d)
for name, f in [("closest-hit (preliminary)", lambda: sc.ray_intersect_preliminary(ray).t),
                ("closest-hit (full interaction)", lambda: sc.ray_intersect(ray).t),
                ("shadow (ray_test)", lambda: sc.ray_test(ray))]:
    rates = []
    for _ in range(7):
        t0 = time.perf_counter()
        r = f()
        dr.eval(r)
        dr.sync_thread()
        rates.append(N / (time.perf_counter() - t0))
    rates.sort()
    print(f"mitsuba {name}: median {rates[3] / 1e6:.2f} M rays/s "
          f"(min {rates[0] / 1e6:.2f}, max {rates[-1] / 1e6:.2f})")
