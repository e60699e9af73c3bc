#!/usr/bin/env bash
# `hdm studio MESH --device shm:NAME` under Xvfb: the studio bakes a mesh first (its progress in the
# window), then takes its device from the reference Python driver through the bridge while its own
# servo thread ticks (lockstep, the tool button never held: the surface does not change); the checks
# (studio_bridge_tests) read the surface contact points the driver got back and the bake's report.
# Skips (exit 77) only when no X server can be started.
# Usage: studio_bridge.sh HDM_STUDIO CHECKS PYTHON CLIENT MESH
set -euo pipefail
studio=$1 checks=$2 python=$3 client=$4 mesh=$5
source "$(dirname "$0")/xvfb.sh"
name="hdm-studio-test-$$"
export HDM_BRIDGE_SECRET="studio-bridge-test-secret-$$-0123456789"  # the studio and the driver share it

# The handle (device frame, metres, the workspace centre at the origin; a mesh centred at the
# origin is centred there): down the z axis into the surface, then once round a great circle in the
# xz plane at 0.04 m from the centre, 1 ms per row.
"$python" - "$tmp/path.csv" <<'PY'
import math, sys
with open(sys.argv[1], "w") as f:
    f.write("time_s,device_x_m,device_y_m,device_z_m,tool_on\n")
    rows = [(0.0, 0.0, 0.06 - 0.02 * k / 200) for k in range(201)]
    rows += [(0.04 * math.sin(a), 0.0, 0.04 * math.cos(a)) for a in (2 * math.pi * k / 1200 for k in range(1, 1201))]
    for k, (x, y, z) in enumerate(rows):
        f.write(f"{k * 1e-3!r},{x!r},{y!r},{z!r},0\n")
PY
echo '{"steps": [{"do": "device_end"}]}' >"$tmp/script.json"
studio_with_driver "$name" /dev/null "$mesh" --device "shm:$name" --script script.json --report report.json -- \
  "$tmp/path.csv" --lockstep --timeout 10 --forces "$tmp/forces.csv"
"$checks" "$tmp" "$mesh"
