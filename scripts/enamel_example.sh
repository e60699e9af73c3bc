#!/usr/bin/env bash
# The two-layer example: blobby.off (libcgal-demo) as a molar crown, 1 mm of enamel over dentin;
# drill a cavity through the enamel, cut a fissure that stays in it, smooth the margin, add a cusp
# and undo it (data/scripts/molar_enamel.json). Leaves out/molar*.{hdm,png}.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
hdm="$here/build/bin/hdm"
out="$here/out"
mkdir -p "$out"
[ -x "$hdm" ] || { bash "$here/scripts/setup.sh" && bash "$here/scripts/build.sh"; }
"$hdm" bake "$here/data/meshes/blobby.off" -o "$out/molar.hdm" --slabs 1000
"$hdm" sculpt "$out/molar.hdm" --script "$here/data/scripts/molar_enamel.json" -o "$out/molar_edited.hdm"
"$hdm" render "$out/molar_edited.hdm" -o "$out/molar_edited.png" --view 10,55 --zoom 2.2 --focus 0.45,0.9,0.5
