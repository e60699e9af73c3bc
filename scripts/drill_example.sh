#!/usr/bin/env bash
# The drill in closed loop (hdm sculpt's simulated hand, the proxy's normal force): blobby.off as a
# molar crown, 1 mm of enamel (300 HV) over dentin (55 HV); a drill dwell on the enamel, a pit
# carved through it, the same dwell in the pit (data/scripts/molar_drill.json). Runs the script's
# prefixes (enamel dwell; carve; carve and pit dwell) and prints each dwell's removed volume (the
# displaced surface's enclosed volume before and after), the integral of the rendered force |F| dt
# from the --forces CSV, and removal per N·s against Archard's K·v_s/H. Leaves out/drill/*.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
hdm="$here/build/bin/hdm"
out="$here/out/drill"
mkdir -p "$out"
"$hdm" bake "$here/data/meshes/blobby.off" -o "$out/molar.hdm" --slabs 1000 >/dev/null
/usr/bin/python3 - "$here/data/scripts/molar_drill.json" "$out" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
for name, strokes in (("enamel", s["strokes"][:1]), ("carve", s["strokes"][1:2]), ("pit", s["strokes"][1:3])):
    json.dump(dict(s, strokes=strokes), open(f"{sys.argv[2]}/{name}.json", "w"))
EOF
for run in enamel carve pit; do
  "$hdm" sculpt "$out/molar.hdm" --script "$out/$run.json" -o "$out/$run.hdm" --forces "$out/$run.csv" >/dev/null
done
HDM_PY="$here/build/python" /usr/bin/python3 - "$out" "$here/data/scripts/molar_drill.json" <<'EOF'
import csv, json, math, os, sys
sys.path.insert(0, os.environ["HDM_PY"])
import hdm
import numpy as np
out, script = sys.argv[1], json.load(open(sys.argv[2]))

def volume(path):
    v, f = hdm.load(f"{out}/{path}.hdm").surface()
    return np.einsum("ij,ij->i", v[f[:, 0]], np.cross(v[f[:, 1]], v[f[:, 2]])).sum() / 6

def force_time(run, stroke):
    """Integral of |F| dt [N s] over the tool-on ticks of stroke number `stroke`."""
    total, k, on_before, prev = 0.0, -1, False, None
    for r in csv.DictReader(open(f"{out}/{run}.csv")):
        t, on = float(r["time_s"]), r["tool_on"] == "1"
        k += on and not on_before
        if on and k == stroke and prev is not None:
            total += math.dist((0, 0, 0), [float(r[c]) for c in ("force_x_n", "force_y_n", "force_z_n")]) * (t - prev)
        on_before, prev = on, t

    return total

m = hdm.load(f"{out}/molar.hdm")
p = m.field("positions")
scale = np.linalg.norm(p.max(0) - p.min(0)) / script["workspace_m"]  # model units per metre (fit_workspace)
mm3 = 1e9 / scale**3  # mm³ per model unit³
rows = [("enamel", volume("molar") - volume("enamel"), force_time("enamel", 0), 300.0),
        ("dentin", volume("carve") - volume("pit"), force_time("pit", 1), script["under_layer"]["hardness_hv"])]
rate = {}
for name, v, fdt, hv in rows:
    st = script["strokes"][0]
    archard = st["wear_coefficient"] * 2 * math.pi * st["rpm"] / 60 * st["radius_mm"] * 1e-3 / (hv * 9.80665e6) * 1e9
    rate[name] = v * mm3 / fdt
    print(f"{name}: removed {v * mm3:.4g} mm3, integral |F| dt {fdt:.4g} N s, {rate[name]:.4g} mm3/(N s), "
          f"Archard K v_s / H {archard:.4g} mm3/(N s) ({rate[name] / archard:.3f})")
print(f"dentin / enamel removal per N s: {rate['dentin'] / rate['enamel']:.3f} (hardness ratio {300.0 / rows[1][3]:.3f})")
EOF
