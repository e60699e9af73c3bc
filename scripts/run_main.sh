#!/usr/bin/env bash
# The main job on the default real model: set up, build, bake bunny00.off into slabs, run the
# default sculpting script in a closed 1 kHz servo loop (edits every tick), export the edited
# surface and render a close-up of the strokes.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/setup.sh"
bash "$here/scripts/build.sh"
hdm="$here/build/bin/hdm"
out="$here/out"
mkdir -p "$out"
"$hdm" bake "$here/data/meshes/bunny00.off" -o "$out/bunny.hdm"
"$hdm" sculpt "$out/bunny.hdm" -o "$out/bunny_edited.hdm" --forces "$out/bunny_forces.csv"
"$hdm" export "$out/bunny_edited.hdm" -o "$out/bunny_edited.glb"
"$hdm" render "$out/bunny_edited.hdm" -o "$out/bunny_edited.png" --view 15,10 --zoom 2.4 --focus 0.63,0.5,0.9
echo
echo "Files:"
for f in bunny.hdm bunny_edited.hdm bunny_edited.glb bunny_edited.png bunny_forces.csv; do
  echo "  $out/$f"
done
