#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Throughput of hdm.Model.query on 1M points (target: <= 0.2 s on a 2-core machine).

Two point sets on one model: "near" (displaced-surface vertices moved along their normal by up to
+-0.2 % of the diagonal: almost all in slabs, the haptic query proper) and "box" (uniform in the
slab box grown by 10 %: most points in no slab, answered by the inside test). Prints the best and
median of --repeat timed calls after one warm-up call (which also builds anything lazy).

    PYTHONPATH=build/python /usr/bin/python3 bench/query_throughput.py [model.hdm or mesh] [--points N]

Compare two builds in one run (the machine is shared: ratios, not absolute times) by running the
script under each PYTHONPATH back to back, or with --compare OTHER_PYTHONPATH.
"""
import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np


def point_sets(model, n, seed=1):
    rng = np.random.default_rng(seed)
    v, f = model.surface()
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    normal = np.cross(b - a, c - a)
    normal /= np.maximum(np.linalg.norm(normal, axis=1), 1e-300)[:, None]
    lo, hi = model.box if hasattr(model, "box") else (v.min(0), v.max(0))  # older modules: the surface's box
    diag = np.linalg.norm(hi - lo)
    pick = rng.integers(0, len(f), n)
    w = rng.dirichlet((1, 1, 1), n)
    near = a[pick] * w[:, :1] + b[pick] * w[:, 1:2] + c[pick] * w[:, 2:]
    near += normal[pick] * rng.uniform(-0.002, 0.002, (n, 1)) * diag
    grow = 0.05 * (hi - lo)
    box = rng.uniform(lo - grow, hi + grow, (n, 3))
    return {"near": near, "box": box}


def measure(args):
    import hdm

    if args.model.endswith(".hdm"):
        model = hdm.load(args.model)
    else:
        model, _ = hdm.bake(args.model)
    sets = point_sets(model, args.points)
    out = {"module": hdm.__file__, "slabs": model.slab_count, "points": args.points}
    for name, p in sets.items():
        q = model.query(p)  # warm-up
        times, cpu = [], []
        for _ in range(args.repeat):
            t, c = time.perf_counter(), time.process_time()
            model.query(p)
            times.append(time.perf_counter() - t)
            cpu.append(time.process_time() - c)
        out[name] = {"best_s": min(times), "median_s": float(np.median(times)), "cpu_s": min(cpu),
                     "in_slab": float(np.mean(q["slab"] >= 0)), "inside": float(np.mean(q["inside"]))}
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("model", nargs="?", default="data/meshes/bunny00.off", help=".hdm file or a mesh to bake")
    ap.add_argument("--points", type=int, default=1_000_000)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--compare", help="PYTHONPATH of another build of the module: run both, alternating")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    if not args.compare:
        r = measure(args)
        if args.json:
            print(json.dumps(r))
        else:
            print(f"{r['module']}: {r['slabs']} slabs, {r['points']} points")
            for name in ("near", "box"):
                s = r[name]
                print(f"  {name:4s} best {s['best_s']:.3f} s, median {s['median_s']:.3f} s, CPU {s['cpu_s']:.3f} s "
                      f"({100 * s['in_slab']:.0f} % in a slab, {100 * s['inside']:.0f} % inside)")
        return
    cmd = [sys.executable, __file__, args.model, "--points", str(args.points), "--repeat", str(args.repeat), "--json"]
    runs = {}
    for label, path in (("this", os.environ.get("PYTHONPATH", "")), ("other", args.compare)) * 2:
        env = dict(os.environ, PYTHONPATH=path)
        run = subprocess.run(cmd, env=env, capture_output=True, text=True)
        if run.returncode:
            sys.exit(f"{label} ({path}) failed:\n{run.stderr}")
        r = json.loads(run.stdout)
        for name in ("near", "box"):
            runs.setdefault((label, name), []).append((r[name]["best_s"], r[name]["cpu_s"]))
    for name in ("near", "box"):
        a, b = min(runs[("this", name)]), min(runs[("other", name)])
        print(f"{name:4s} this {a[0]:.3f} s (CPU {a[1]:.3f} s), other {b[0]:.3f} s (CPU {b[1]:.3f} s), "
              f"other/this {b[0] / a[0]:.1f}x wall, {b[1] / a[1]:.1f}x CPU")


if __name__ == "__main__":
    main()
