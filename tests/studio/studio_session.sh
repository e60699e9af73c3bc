#!/usr/bin/env bash
# The studio under Xvfb with a scripted session (carve, paint, undo, live stiffness, the brush's
# footprint), then the checks on what it left (studio_session_tests). Skips (exit 77) only when no
# X server can be started.
# Usage: studio_session.sh HDM HDM_STUDIO CHECKS MESH SCRIPT [STUDIO_OPTIONS...]
set -euo pipefail
hdm=$1 studio=$2 checks=$3 mesh=$4 script=$5
shift 5
source "$(dirname "$0")/xvfb.sh"

"$hdm" bake "$mesh" -o "$tmp/model.hdm" --slabs 300 --no-error-bound >/dev/null
# Full detail throughout (--lod 0): the mouse's handle goes in from the surface drawn, so an automatic
# level change, which a loaded machine triggers, would move the handle between the two probes.
(cd "$tmp" && "$studio" model.hdm --size 1280x720 --lod 0 --script "$script" --report report.json --verify-uploads "$@")
"$checks" "$tmp" "$script"
