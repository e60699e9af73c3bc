#!/usr/bin/env bash
# The studio under Xvfb with a scripted session (carve, paint, undo), then the checks on what it
# left (studio_session_tests). Skips (exit 77) only when no X server can be started.
# Usage: studio_session.sh HDM HDM_STUDIO CHECKS MESH SCRIPT
set -euo pipefail
hdm=$1 studio=$2 checks=$3 mesh=$4 script=$5

if ! command -v Xvfb >/dev/null; then
  echo "SKIPPED: Xvfb is not installed (apt-get install xvfb): the studio test needs an X server" >&2
  exit 77
fi
tmp=$(mktemp -d)
xvfb=""
cleanup() {
  [ -n "$xvfb" ] && kill "$xvfb" 2>/dev/null && wait "$xvfb" 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
# -displayfd: Xvfb picks a free display and writes its number once it accepts connections.
Xvfb -displayfd 3 -screen 0 1280x720x24 -nolisten tcp 3>"$tmp/display" 2>"$tmp/xvfb.log" &
xvfb=$!
for _ in $(seq 200); do
  [ -s "$tmp/display" ] && break
  kill -0 "$xvfb" 2>/dev/null || break
  sleep 0.05
done
if [ ! -s "$tmp/display" ]; then
  echo "SKIPPED: no X server could be started (Xvfb: $(tr '\n' ' ' <"$tmp/xvfb.log"))" >&2
  exit 77
fi
export DISPLAY=":$(head -n1 "$tmp/display")"

"$hdm" bake "$mesh" -o "$tmp/model.hdm" --slabs 300 --no-error-bound >/dev/null
(cd "$tmp" && "$studio" model.hdm --size 1280x720 --script "$script" --report report.json --verify-uploads)
"$checks" "$tmp" "$script"
