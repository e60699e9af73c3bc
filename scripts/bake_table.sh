#!/usr/bin/env bash
# Bakes the real models and measures each against its input with `hdm check`; prints a Markdown
# table (docs/figures.md). Usage: scripts/bake_table.sh [extra bake arguments...]
# With no arguments the defaults apply: slab count from --density 4, raised until the fidelity
# bound (0.2% max, 0.02% RMS, both ways) holds; then a few fixed-count rows for comparison.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
hdm="${HDM:-$here/build/bin/hdm}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
echo "| model | slabs | n | input tris | submesh tris | bake s (last round / command) | misses | invalid | overlapping pairs | undercut cols | RMS % | max % | RMS back % | max back % | contact agreement | depth RMS % | depth max % |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
run() {
  local model="$1"; shift
  "$hdm" bake "$here/data/meshes/$model" -o "$tmp/m.hdm" --json "$@" > "$tmp/bake.json"
  "$hdm" check "$tmp/m.hdm" --against "$here/data/meshes/$model" --json > "$tmp/check.json"
  python3 - "$model" "$*" "$tmp/bake.json" "$tmp/check.json" <<'PY'
import json, sys
name, args, b, c = sys.argv[1], sys.argv[2], json.load(open(sys.argv[3])), json.load(open(sys.argv[4]))
f, k = c["fidelity"], c["contact"]
label = name + (f" `{args}`" if args else "")
print(f"| {label} | {b['slabs']} | {b['grid']} | {b['input_triangles']} | {b['submesh_triangles']} | {b['bake_seconds']:.2f} / {b['total_seconds']:.1f} | "
      f"{b['ray_misses']} | {c['invalid_slabs']} | {c['overlapping_pairs']} | {c['undercut_columns']} | "
      f"{f['rms_pct']:.4f} | {f['max_pct']:.3f} | {f['rms_back_pct']:.4f} | {f['max_back_pct']:.3f} | "
      f"{100*k['agreement']:.2f}% | {k['depth_rms_pct']:.4f} | {k['depth_max_pct']:.3f} |")
PY
}
for m in bunny00.off armadillo.off refined_elephant.off lion-head.off; do run "$m" "$@"; done
if [ $# -eq 0 ]; then
  run bunny00.off --slabs 150 --grid 15
  run bunny00.off --density 1 --no-error-bound
  run bunny00.off --density 1 --grid 8 --no-error-bound
  run bunny00.off --density 2.25 --grid 12 --no-error-bound
  run armadillo.off --no-error-bound
fi
