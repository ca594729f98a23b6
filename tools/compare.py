#!/usr/bin/env python3
"""Compare two linear EXR renders: per-channel means, 8x8-block relative differences.
usage: python3 tools/compare.py A.exr B.exr"""
import sys
import numpy as np
import mitsuba as mi
mi.set_variant("scalar_rgb")
a = np.array(mi.Bitmap(sys.argv[1]))[..., :3].astype(np.float64)
b = np.array(mi.Bitmap(sys.argv[2]))[..., :3].astype(np.float64)
print("shape", a.shape, b.shape)
print("mean A", a.mean(axis=(0, 1)), "mean B", b.mean(axis=(0, 1)))
print("ratio A/B", a.mean(axis=(0, 1)) / b.mean(axis=(0, 1)))
h, w = a.shape[0] // 8 * 8, a.shape[1] // 8 * 8
ba = a[:h, :w].reshape(h // 8, 8, w // 8, 8, 3).mean(axis=(1, 3))
bb = b[:h, :w].reshape(h // 8, 8, w // 8, 8, 3).mean(axis=(1, 3))
rel = np.abs(ba - bb) / (np.abs(bb) + 0.02)
print("block rel diff: median %.4f  p90 %.4f  max %.4f" % (np.median(rel), np.percentile(rel, 90), rel.max()))
idx = np.unravel_index(np.argmax(rel), rel.shape)
print("worst block", idx, "A", ba[idx[0], idx[1]], "B", bb[idx[0], idx[1]])
