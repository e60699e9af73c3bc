#!/usr/bin/env bash
# The studio in lockstep (--ticks-per-frame): the same scripted burr session, drilling included, run
# twice under Xvfb, then the checks compare the two reports (studio_lockstep_tests). Skips (exit 77)
# only when no X server can be started.
# Usage: studio_lockstep.sh HDM HDM_STUDIO CHECKS MESH SCRIPT TICKS_PER_FRAME
set -euo pipefail
hdm=$1 studio=$2 checks=$3 mesh=$4 script=$5 ticks=$6
source "$(dirname "$0")/xvfb.sh"

"$hdm" bake "$mesh" -o "$tmp/model.hdm" --slabs 300 --no-error-bound >/dev/null
for run in a b; do
  (cd "$tmp" && "$studio" model.hdm --size 1280x720 --lod 0 --burr --ticks-per-frame "$ticks" --script "$script" \
    --report "report_$run.json")
done
"$checks" "$tmp" "$ticks"
