#!/usr/bin/env bash
# Sourced by the studio's tests: starts Xvfb on a free display (exports DISPLAY), makes $tmp, and
# cleans both up on exit. Exits 77 (ctest "Skipped") only when no X server can be started.
if ! command -v Xvfb >/dev/null; then
  echo "SKIPPED: Xvfb is not installed (apt-get install xvfb): the studio test needs an X server" >&2
  exit 77
fi
tmp=$(mktemp -d)
xvfb=""
cleanup_extra=""
cleanup() {
  [ -n "$cleanup_extra" ] && eval "$cleanup_extra"
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
