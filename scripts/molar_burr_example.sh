#!/usr/bin/env bash
# A molar drilled with the 6-DOF burr in the studio: scripts/molar_crown.py writes a crown with four
# cusps around a central fossa, with 1 mm of enamel (300 HV) over dentin (55 HV, orange);
# `hdm studio --burr` with the drill brush holds the burr upright 2 mm into the fossa for 900 frames
# (data/scripts/studio_molar_burr.json; the servo loop in lockstep, 100 ticks a frame, so that
# every run gives the same figures), then holds it 1 mm into the pit and tilts it toward a cusp:
# at 53° the head alone touches (probe "tilted"), 10° further the shaft rests on the cusp's inner
# slope (probe "shaft_on_cusp": head and shaft contacts, the torque), and the window is saved from
# the side about the tip. Needs an X display, or runs under Xvfb.
# Leaves out/molar_burr/{molar.off,molar.hdm,molar_layers.hdm,molar_burr.png,report.json}.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$here/out/molar_burr"
mkdir -p "$out"
/usr/bin/python3 "$here/scripts/molar_crown.py" "$out/molar.off"
"$here/build/bin/hdm" bake "$out/molar.off" -o "$out/molar.hdm" --slabs 1000 >/dev/null
PYTHONPATH="$here/build/python" /usr/bin/python3 - "$out" <<'PY'
import sys
import hdm
import numpy as np
out = sys.argv[1]
m = hdm.load(f"{out}/molar.hdm")
p = m.field("positions")
mm = np.linalg.norm(p.max(0) - p.min(0)) / 0.16 / 1000  # model units per mm (the studio's 0.16 m workspace)
m.set_under_layer(1.0 * mm, colour=[0.78, 0.5, 0.18], hardness_hv=55)
m.save(f"{out}/molar_layers.hdm")
PY
run=()
[ -n "${DISPLAY:-}" ] || run=(xvfb-run -a -s "-screen 0 1280x720x24")
(cd "$out" && "${run[@]}" "$here/build/bin/hdm-studio" molar_layers.hdm --size 1280x720 --lod 0 --burr \
  --ticks-per-frame 100 \
  --script "$here/data/scripts/studio_molar_burr.json" --report report.json)
echo "wrote $out/molar_burr.png"
