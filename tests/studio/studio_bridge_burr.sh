#!/usr/bin/env bash
# `hdm studio MESH --burr --device shm:NAME` under Xvfb with the reference Python driver sending the
# handle's orientation (the trajectory's device_qw..device_qz columns) in free space: the burr's
# god-object, which follows the handle there, ends turned as the driver's last row says (probe
# "end" after the driver's end packet, compared here with the row's quaternion, sign-free), and the
# driver's forces CSV has the torque columns. A second run lowers the tilted burr onto the sphere:
# the driver receives the burr's torque (the studio reports a 6-DOF device spec with --burr).
# The driver waits for each answer (--lockstep), so a slow tick (an instrumented build on a loaded
# machine answers 15-30 ms late at p99) is not a silent device: the watchdog is set to 1 s (at its
# 5 ms default it tripped there and ramped the force out, 0 N in one run in five).
# Skips (exit 77) only when no X server can be started.
# Usage: studio_bridge_burr.sh HDM_STUDIO PYTHON CLIENT MESH
set -euo pipefail
studio=$1 python=$2 client=$3 mesh=$4
source "$(dirname "$0")/xvfb.sh"
name="hdm-studio-burr-test-$$"
export HDM_BRIDGE_SECRET="studio-bridge-burr-test-secret-$$-0123456789"

# 600 rows, 1 ms apart, far above the surface (free space): the handle turns from the identity by
# 70° about the axis (1, 2, 2)/3 over the first 300 rows, then holds.
"$python" - "$tmp/path.csv" <<'PY'
import math, sys
with open(sys.argv[1], "w") as f:
    f.write("time_s,device_x_m,device_y_m,device_z_m,tool_on,device_qw,device_qx,device_qy,device_qz\n")
    for k in range(600):
        a = math.radians(70) * min(k, 300) / 300
        s = math.sin(a / 2) / 3
        f.write(f"{k * 1e-3!r},0.0,0.12,0.0,0,{math.cos(a / 2)!r},{s!r},{2 * s!r},{2 * s!r}\n")
PY
echo '{"steps": [{"do": "device_end"}, {"do": "probe", "name": "end"}]}' >"$tmp/script.json"
studio_with_driver "$name" /dev/null "$mesh" --burr --device "shm:$name" --watchdog-ms 1000 --script script.json --report report.json -- \
  "$tmp/path.csv" --lockstep --timeout 10 --forces "$tmp/forces.csv"
"$python" - "$tmp/report.json" "$tmp/forces.csv" <<'PY'
import json, math, sys
probe = json.load(open(sys.argv[1]))["probes"]["end"]
got = probe["orientation_wxyz"]
a = math.radians(70)
want = (math.cos(a / 2), math.sin(a / 2) / 3, 2 * math.sin(a / 2) / 3, 2 * math.sin(a / 2) / 3)
angle = math.degrees(2 * math.acos(min(1.0, abs(sum(g * w for g, w in zip(got, want))))))
print(f"the burr ends {angle:.3f} degrees from the driver's last orientation")
assert angle < 1.0, (got, want)
header = open(sys.argv[2]).readline().strip().split(",")
assert header[-3:] == ["torque_x_nm", "torque_y_nm", "torque_z_nm"], header
PY

# The burr turned 70° as above, then lowered from 0.12 m to 0.03 m above the sphere's centre (its
# surface is about 0.05 m from it in the workspace) and held there.
"$python" - "$tmp/press.csv" <<'PY'
import math, sys
a = math.radians(70)
s = math.sin(a / 2) / 3
q = f"{math.cos(a / 2)!r},{s!r},{2 * s!r},{2 * s!r}"
with open(sys.argv[1], "w") as f:
    f.write("time_s,device_x_m,device_y_m,device_z_m,tool_on,device_qw,device_qx,device_qy,device_qz\n")
    for k in range(1200):
        y = 0.12 - 0.09 * min(k, 900) / 900
        f.write(f"{k * 1e-3!r},0.0,{y!r},0.0,0,{q}\n")
PY
echo '{"steps": [{"do": "device_end"}]}' >"$tmp/script2.json"
name2="$name-press"
studio_with_driver "$name2" "$tmp/press.json" "$mesh" --burr --device "shm:$name2" --watchdog-ms 1000 --script script2.json -- \
  "$tmp/press.csv" --lockstep --timeout 10
"$python" - "$tmp/press.json" "${HDM_SANITIZED:-0}" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"pressing the tilted burr: max force {s['max_force_n']:.3f} N, max torque {s['max_torque_nm'] * 1000:.2f} mN·m")
# Any torque at all: a 3-DOF spec sends exactly 0. Under the sanitizers (scripts/test_asan.sh sets
# HDM_SANITIZED=1) the instrumented servo loop misses ticks, and the burr presses less deep (0.05-0.4 N
# against 3.3 N) or, in about one run in six, not at all (0 N with the device 2 cm inside the sphere:
# the rigid tool's god-object falls through under slow ticks, docs/studio.md). There the run checks
# memory errors along the press and the figures are printed; the force is asserted in the main lane.
if sys.argv[2] != "1":
    assert s["max_force_n"] > 0.01, s
    assert s["max_torque_nm"] > 0, s
PY
