#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Bake the bunny, drag a probe along a straight path that dips into its back, and print (or plot,
with matplotlib when installed) the penetration depth and the rendered force a 1000 N/m spring
would give, F = k * depth along the normal, against the path parameter.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/query_path.py [data/meshes/bunny00.off]
"""
import sys

import numpy as np

import hdm

path = sys.argv[1] if len(sys.argv) > 1 else "data/meshes/bunny00.off"
model, report = hdm.bake(path)
print(f"{report['slabs']} slabs, n = {report['grid']}, max error {report['fidelity']['max_pct']:.3f} % "
      f"of the diagonal, bound met: {report['bound_met']}")

# The path: across the model's bounding box at mid height, from the top surface down into it.
vertices, _ = model.surface()
lo, hi = vertices.min(0), vertices.max(0)
t = np.linspace(0, 1, 2000)
start = np.array([lo[0], hi[1], 0.5 * (lo[2] + hi[2])])
end = np.array([hi[0], 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])])
points = start + t[:, None] * (end - start)
q = model.query(points)

stiffness = 1000.0  # N/m, with model units read as metres for this illustration
depth = np.where(q["slab"] >= 0, np.maximum(q["depth"], 0), 0)
force = stiffness * depth[:, None] * np.nan_to_num(q["normal"])
first = np.argmax(q["inside"]) if q["inside"].any() else None
print(f"{q['inside'].sum()} of {len(t)} path points inside; first contact at t = "
      f"{t[first]:.3f}" if first is not None else "no contact on this path")
try:
    import matplotlib.pyplot as plt
except ImportError:
    for k in range(0, len(t), 200):
        print(f"t {t[k]:.2f}  slab {q['slab'][k]:5d}  depth {depth[k]:.5f}  |F| {np.linalg.norm(force[k]):.3f} N")
else:
    plt.plot(t, np.linalg.norm(force, axis=1))
    plt.xlabel("path parameter")
    plt.ylabel("|F| [N]")
    plt.title(f"{path}: spring force along the path")
    plt.savefig("query_path.png", dpi=120)
    print("wrote query_path.png")
