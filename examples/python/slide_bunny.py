#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Bake the bunny, slide a haptic probe over its back and plot the rendered force against time.

A simulated hand (hdm.SimulatedDevice: a 50 g handle on a 200 N/m hand spring) follows a path
across the top of the model, below the surface so that it presses with about 1 N; each servo tick at 1 kHz runs the proxy (god-object) on the displaced surface and the
force goes back to the handle (hdm.run_device). The force is plotted with matplotlib when it is
installed (else printed), together with the same path rendered open loop (hdm.proxy_step).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/slide_bunny.py [data/meshes/bunny00.off]
"""
import sys

import numpy as np

import hdm

path = sys.argv[1] if len(sys.argv) > 1 else "data/meshes/bunny00.off"
model, report = hdm.bake(path)
print(f"baked {path}: {report['slabs']} slabs, n = {report['grid']}, max error "
      f"{report['fidelity']['max_pct']:.3f} % of the diagonal")

# The path: along x across the middle of the box, just below the highest surface point of each
# column (y up), smoothed so that the hand moves steadily; 2 s at 1 kHz.
ws = hdm.fit_workspace(model)  # the model's diagonal fits a 0.16 m device workspace
vertices, _ = model.surface()
lo, hi = model.box
mid_z = 0.5 * (lo[2] + hi[2])
band = vertices[np.abs(vertices[:, 2] - mid_z) < 0.02 * (hi[2] - lo[2])]
xs = np.linspace(lo[0] + 0.2 * (hi[0] - lo[0]), hi[0] - 0.2 * (hi[0] - lo[0]), 2000)
column = [band[np.abs(band[:, 0] - x) < 0.01 * (hi[0] - lo[0]), 1] for x in xs]
found = np.array([len(c) > 0 for c in column])
top = np.interp(xs, xs[found], [c.max() for c in column if len(c)])
top = np.convolve(np.pad(top, 50, mode="edge"), np.ones(101) / 101, mode="valid")
params = hdm.ProxyParams()  # 1000 N/m, 1 N·s/m, 3.3 N: a desktop device
press_n, hand_n_per_m = 1.0, 200.0
top_points = np.stack([xs, top, np.full_like(xs, mid_z)], axis=1)


def below(depth_m):
    """The path depth_m metres (at the device) below the top line, in the device frame."""
    return ws.to_device(top_points - [0, depth_m * ws.scale, 0])


# Closed loop: the hand spring and the rendered spring in series press with press_n when the hand
# aims press_n / k_hand + press_n / k below the surface (6 mm).
targets = below(press_n / hand_n_per_m + press_n / params.stiffness)
device = hdm.SimulatedDevice(targets, start=targets[0] + [0, 0.01, 0], hand_stiffness=hand_n_per_m)
closed = hdm.run_device(model, device, len(targets), params=params)
# Open loop: the HIP itself follows the path press_n / k (1 mm) below the top line.
open_loop = hdm.proxy_step(model, below(press_n / params.stiffness), hdm.ProxyState(), params=params)

force = np.linalg.norm(closed["force"], axis=1)
contact = closed["slab"] >= 0
print(f"{contact.mean() * 100:.0f} % of ticks in contact; force in contact: mean {force[contact].mean():.2f} N, "
      f"max {force.max():.2f} N; open loop: mean {np.linalg.norm(open_loop['force'], axis=1).mean():.2f} N")
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    for k in range(0, len(force), 200):
        print(f"t {closed['time'][k]:.2f} s  |F| {force[k]:.3f} N  slab {closed['slab'][k]}")
else:
    plt.figure(figsize=(8, 3.5))
    plt.plot(closed["time"], force, label="simulated hand (closed loop)")
    plt.plot(open_loop["time"], np.linalg.norm(open_loop["force"], axis=1), label="path (open loop)", alpha=0.7)
    plt.xlabel("time [s]")
    plt.ylabel("|F| [N]")
    plt.title(f"{path}: sliding over the back")
    plt.legend()
    plt.tight_layout()
    plt.savefig("slide_bunny.png", dpi=120)
    print("wrote slide_bunny.png")
