#!/usr/bin/env bash
# Validity sweep (target: zero invalid slabs and zero overlapping pairs at every slab count from 150
# to 20,000): bakes each model at each count and prints `hdm check`'s invalid slabs and overlapping
# pairs. The grid is n = 4: validity depends on the coarse shell only, not on n.
# Usage: scripts/validity_sweep.sh [mesh files...]   (default: the four libcgal-demo models)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
hdm="${HDM:-$here/build/bin/hdm}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
meshes=("$@")
[ ${#meshes[@]} -gt 0 ] || meshes=("$here"/data/meshes/{bunny00,armadillo,refined_elephant,lion-head}.off)
echo "| model | slabs (target) | slabs | bake s | invalid | overlapping pairs | misses | RMS % | max back % |"
echo "|---|---|---|---|---|---|---|---|---|"
for m in "${meshes[@]}"; do
  for n in 150 500 2000 5000 20000; do
    if ! "$hdm" bake "$m" --slabs "$n" --grid 4 -o "$tmp/m.hdm" --json > "$tmp/b.json" 2> "$tmp/err"; then
      echo "| $(basename "$m") | $n | bake failed: $(tail -1 "$tmp/err") | | | | | | |"
      continue
    fi
    "$hdm" check "$tmp/m.hdm" --against "$m" --points 20000 --json > "$tmp/c.json"
    python3 - "$(basename "$m")" "$n" "$tmp/b.json" "$tmp/c.json" <<'PY'
import json, sys
name, n, b, c = sys.argv[1], sys.argv[2], json.load(open(sys.argv[3])), json.load(open(sys.argv[4]))
f = c["fidelity"]
print(f"| {name} | {n} | {b['slabs']} | {b['bake_seconds']:.2f} | {c['invalid_slabs']} | {c['overlapping_pairs']} | "
      f"{b['ray_misses']} | {f['rms_pct']:.4f} | {f['max_back_pct']:.3f} |")
PY
  done
done
