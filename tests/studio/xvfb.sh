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

# studio_with_driver NAME OUT STUDIO_ARGS... -- DRIVER_ARGS...: runs "$studio" with STUDIO_ARGS in
# $tmp, waits for its shared-memory region NAME (it appears once the bake is done and the session
# starts), runs the Python driver "$python" "$client" --shm NAME DRIVER_ARGS with its output in
# OUT, and waits for the studio to exit.
studio_with_driver() {
  local name=$1 out=$2 studio_args=()
  shift 2
  while [ "$1" != "--" ]; do
    studio_args+=("$1")
    shift
  done
  shift
  (cd "$tmp" && exec "$studio" "${studio_args[@]}") &
  local studio_pid=$!
  cleanup_extra="kill $studio_pid 2>/dev/null || true"
  for _ in $(seq 1200); do
    [ -e "/dev/shm/$name" ] && break
    kill -0 "$studio_pid" 2>/dev/null || break
    sleep 0.05
  done
  "$python" "$client" --shm "$name" "$@" >"$out"
  wait "$studio_pid"
  cleanup_extra=""
}
