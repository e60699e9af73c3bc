#!/usr/bin/env bash
# Bakes an input of at least 1,000,000 triangles at 20,000 slabs, n = 16.
# Makes data/meshes/armadillo_1m.off (armadillo.off after three sqrt(3) subdivision steps with
# CGAL: 52,000 -> 1,404,000 triangles) if it is missing, bakes it and prints the bake time, the
# wall time of the command and the peak resident memory; with CHECK=1 also runs `hdm check`.
# Usage: HDM=build/bin/hdm [MESH=path.off] [SLABS=20000] [GRID=16] [CHECK=1] scripts/bake_million.sh
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
hdm="${HDM:-$here/build/bin/hdm}"
mesh="${MESH:-$here/data/meshes/armadillo_1m.off}"
slabs="${SLABS:-20000}"
grid="${GRID:-16}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
if [ ! -f "$mesh" ]; then
  echo "making $mesh" >&2
  "$hdm" subdivide "$here/data/meshes/armadillo.off" -o "$mesh" --min-triangles 1000000 >&2
fi
t0=$(date +%s.%N)
"$hdm" bake "$mesh" -o "$tmp/m.hdm" --slabs "$slabs" --grid "$grid" --json > "$tmp/bake.json"
t1=$(date +%s.%N)
echo "{}" > "$tmp/check.json"
if [ "${CHECK:-0}" = 1 ]; then
  "$hdm" check "$tmp/m.hdm" --against "$mesh" --json > "$tmp/check.json"
fi
python3 - "$mesh" "$tmp/bake.json" "$tmp/check.json" "$t0" "$t1" <<'PY'
import json, sys
mesh, b, c = sys.argv[1], json.load(open(sys.argv[2])), json.load(open(sys.argv[3]))
wall = float(sys.argv[5]) - float(sys.argv[4])
f = b["fidelity"]
print(f"input          {mesh} ({b['input_triangles']} triangles)")
print(f"slabs          {b['slabs']} (n = {b['grid']}, {b['samples']} samples, {b['submesh_triangles']} submesh triangles)")
print(f"bake time      {b['bake_seconds']:.2f} s (whole command, with reading, repair check and fidelity: {wall:.2f} s)")
print(f"peak RSS       {b['peak_rss_mib']:.0f} MiB")
print(f"bake report    invalid {b['invalid_slabs']}, ray misses {b['ray_misses']}, undercut columns {b['undercut_columns']}")
print(f"fidelity       RMS {f['rms_pct']:.4f}% max {f['max_pct']:.3f}%, back RMS {f['rms_back_pct']:.4f}% max {f['max_back_pct']:.3f}%")
if c:
    k, g = c["contact"], c["fidelity"]
    print(f"hdm check      invalid {c['invalid_slabs']}, overlapping pairs {c['overlapping_pairs']}, "
          f"undercut columns {c['undercut_columns']}, RMS {g['rms_pct']:.4f}% max {g['max_pct']:.3f}%, "
          f"back RMS {g['rms_back_pct']:.4f}% max {g['max_back_pct']:.3f}%, agreement {100*k['agreement']:.2f}%")
PY
