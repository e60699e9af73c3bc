#!/usr/bin/env bash
# Fault injection against the hdm program (docs/reliability.md): kills during saves, planted links
# and files at every temporary name, concurrent saves, a full and a read-only file system for every
# writer, memory refusals, the bridge under a restarting driver, forged packets and a wrong secret,
# and every command's exit code for a bad option. Prints one line per part with its counts and
# fails on the first broken promise. About 80 s.
#
# Usage: bash scripts/fault_injection.sh [BUILD_DIR]   (default build/; needs build/bin/hdm and
# data/meshes from scripts/setup.sh). KILLS=N changes the number of kills (default 100); PARTS="..."
# runs only the parts named (kill_saves kill_exports planted concurrent full_and_readonly memory
# bridge exit_codes).
# A full and a read-only file system are small tmpfs mounts when this user may mount (root);
# otherwise a file size limit (ulimit -f) and an unprivileged user's write into a root directory
# stand in for them.
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$here/build}"
hdm="$build/bin/hdm"
meshes="$here/data/meshes"
client="$here/examples/python/bridge_client.py"
kills="${KILLS:-100}"
[ -x "$hdm" ] || { echo "fault_injection: no $hdm (build first)" >&2; exit 1; }
[ -f "$meshes/sphere.off" ] || { echo "fault_injection: no $meshes/sphere.off (scripts/setup.sh)" >&2; exit 1; }
work=$(mktemp -d)
mounts=()
cleanup() {
  for m in "${mounts[@]}"; do umount "$m" 2>/dev/null; done
  chmod -R u+w "$work" 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "fault_injection: FAIL: $*" >&2; exit 1; }
sha() { sha256sum <"$1" | cut -c1-64; }
temporaries() { find "$1" -maxdepth 1 -name '.*.tmp' | wc -l; }

# ---- fixtures: an old and a new model (different bytes), a script that probes without editing ----
"$hdm" bake "$meshes/sphere.off" -o "$work/new.hdm" --slabs 300 --grid 16 --texels 4 --no-error-bound >/dev/null ||
  fail "cannot bake the fixture"
"$hdm" bake "$meshes/sphere.off" -o "$work/old.hdm" --slabs 40 --grid 4 --no-error-bound >/dev/null ||
  fail "cannot bake the fixture"
cat >"$work/probe.json" <<'JSON'
{"strokes": [{"tool": "probe", "from": [0.5, 0.5, 1.0], "to": [0.55, 0.5, 1.0], "speed_mm_s": 100}]}
JSON
# Loading and saving a model without an edit gives its bytes back: the complete new file is known.
save_cmd=("$hdm" sculpt "$work/new.hdm" --script "$work/probe.json" --fast)
"${save_cmd[@]}" -o "$work/ref.hdm" >/dev/null || fail "the save command fails"
[ "$(sha "$work/ref.hdm")" = "$(sha "$work/new.hdm")" ] || fail "a save without edits changed the model's bytes"
sha_old=$(sha "$work/old.hdm") sha_new=$(sha "$work/new.hdm")
mkdir "$work/ref"  # the OBJ names its MTL, the MTL its PNG: the reference has the names of the test
"$hdm" export "$work/new.hdm" -o "$work/ref/out.obj" >/dev/null || fail "cannot export the fixture"

# ---- 1. kill -9 at random points of saves: a model (sculpt -o) and an export set (OBJ+MTL+PNG) ----
kill_saves() {
  local dir="$work/kill" seen=0 old=0 new=0 t0 t1 run_ms
  mkdir -p "$dir"
  t0=$(date +%s%N)
  "${save_cmd[@]}" -o "$dir/out.hdm" >/dev/null
  t1=$(date +%s%N)
  run_ms=$(((t1 - t0) / 1000000 + 1))
  for ((i = 0; i < kills; i++)); do
    cp "$work/old.hdm" "$dir/out.hdm"
    "${save_cmd[@]}" -o "$dir/out.hdm" >/dev/null 2>&1 &
    local pid=$!
    sleep "$(awk -v r=$RANDOM -v t=$run_ms 'BEGIN { printf "%.4f", r / 32767 * t * 1.1 / 1000 }')"
    kill -9 $pid 2>/dev/null
    wait $pid 2>/dev/null
    local s
    s=$(sha "$dir/out.hdm")
    if [ "$s" = "$sha_old" ]; then old=$((old + 1)); elif [ "$s" = "$sha_new" ]; then new=$((new + 1)); else
      fail "kill $i left a model that is neither the old nor the new file"; fi
    "$hdm" info "$dir/out.hdm" >/dev/null || fail "kill $i left a model that does not load"
    seen=$((seen + $(temporaries "$dir")))
  done
  "${save_cmd[@]}" -o "$dir/out.hdm" >/dev/null || fail "the save after the kills failed"
  [ "$(temporaries "$dir")" -eq 0 ] || fail "temporaries left after the next save: $(ls -A "$dir")"
  echo "kills during saves: $kills (run ${run_ms} ms): OUT old $old, new $new, other 0; temporaries right after a kill: $seen, after the next save: 0"
}

kill_exports() {
  local dir="$work/killx" n=$((kills / 2)) mixed=0 t0 t1 run_ms
  mkdir -p "$dir"
  t0=$(date +%s%N)
  "$hdm" export "$work/new.hdm" -o "$dir/out.obj" >/dev/null
  t1=$(date +%s%N)
  run_ms=$(((t1 - t0) / 1000000 + 1))
  for ((i = 0; i < n; i++)); do
    rm -f "$dir"/*
    "$hdm" export "$work/new.hdm" -o "$dir/out.obj" >/dev/null 2>&1 &
    local pid=$!
    sleep "$(awk -v r=$RANDOM -v t=$run_ms 'BEGIN { printf "%.4f", r / 32767 * t * 1.1 / 1000 }')"
    kill -9 $pid 2>/dev/null
    wait $pid 2>/dev/null
    for f in obj mtl png; do  # each file absent (nothing yet) or complete
      [ ! -e "$dir/out.$f" ] || [ "$(sha "$dir/out.$f")" = "$(sha "$work/ref/out.$f")" ] ||
        fail "export kill $i left a partial out.$f"
    done
    [ -e "$dir/out.obj" ] && { [ -e "$dir/out.mtl" ] && [ -e "$dir/out.png" ] || mixed=$((mixed + 1)); }
  done
  [ $mixed -eq 0 ] || fail "an OBJ without its side files after a kill ($mixed times)"
  echo "kills during exports: $n (run ${run_ms} ms): every file absent or complete, no OBJ without its MTL and PNG"
}

# ---- 2. a planted link and a planted file at every temporary name a writer could use ----
# The writer is started by `exec` from a shell that planted first, so its process id is known.
plant_and_run() {  # plant_and_run KIND N OUT... -- COMMAND...: plants N names per output, runs the command
  local kind=$1 n=$2
  shift 2
  local outs=()
  while [ "$1" != -- ]; do outs+=("$1"); shift; done
  shift
  bash -c '
    kind=$1 n=$2 victim=$3 count=$4; shift 4
    outs=("${@:1:$count}"); shift "$count"
    for out in "${outs[@]}"; do
      d=$(dirname "$out") b=$(basename "$out")
      for ((k = 0; k < n; k++)); do
        t="$d/.$b.$$-$k.tmp"
        if [ "$kind" = link ]; then ln -s "$victim" "$t"; else echo planted >"$t"; fi
      done
      if [ "$kind" = link ]; then ln -s "$victim" "$out.tmp"; else echo planted >"$out.tmp"; fi
    done
    exec "$@"' _ "$kind" "$n" "$work/victim" "${#outs[@]}" "${outs[@]}" "$@" >/dev/null 2>"$work/plant.err"
}

planted() {
  local cases=0 refused=0 passed=0
  echo victim >"$work/victim"
  for kind in link file; do
    for n in 100 30; do
      for writer in model csv obj ply off trace; do
        local dir="$work/plant-$kind-$n-$writer"
        mkdir -p "$dir"
        local outs=() cmd=()
        case $writer in
        model) outs=("$dir/m.hdm") cmd=("${save_cmd[@]}" -o "$dir/m.hdm") ;;
        csv) outs=("$dir/f.csv") cmd=("${save_cmd[@]}" --forces "$dir/f.csv") ;;
        obj) outs=("$dir/e.obj" "$dir/e.mtl" "$dir/e.png") cmd=("$hdm" export "$work/old.hdm" -o "$dir/e.obj") ;;
        ply) outs=("$dir/e.ply") cmd=("$hdm" export "$work/old.hdm" -o "$dir/e.ply") ;;
        off) outs=("$dir/s.off") cmd=("$hdm" subdivide "$meshes/tetrahedron.off" -o "$dir/s.off" --min-triangles 10) ;;
        trace) outs=("$dir/t.csv") cmd=("$hdm" feel "$work/old.hdm" --input "$meshes/sphere.off" --scenario press --trace "$dir/t.csv") ;;
        esac
        [ "$writer" = off ] && [ ! -f "$meshes/tetrahedron.off" ] && continue
        local before
        before=$(ls -A "$dir" | sort | tr '\n' ' ')
        local rc=0
        plant_and_run "$kind" "$n" "${outs[@]}" -- "${cmd[@]}" || rc=$?
        cases=$((cases + 1))
        [ "$(cat "$work/victim")" = victim ] || fail "$writer followed a planted link ($kind, $n names)"
        for f in "$dir"/.*.tmp "$dir"/*.tmp; do
          [ -e "$f" ] || [ -L "$f" ] || continue
          if [ "$kind" = link ]; then [ -L "$f" ] || fail "$writer replaced the planted link $f"; else
            [ "$(cat "$f")" = planted ] || fail "$writer wrote into the planted file $f"; fi
        done
        if [ "$n" = 100 ]; then  # every name taken: a clean refusal, nothing new
          [ $rc -eq 1 ] || fail "$writer with every name taken exited $rc"
          grep -q "names taken" "$work/plant.err" || fail "$writer: unclear error: $(cat "$work/plant.err")"
          [ "$(find "$dir" -maxdepth 1 ! -name '*.tmp' -type f | wc -l)" -eq 0 ] || fail "$writer left an output"
          refused=$((refused + 1))
        else
          [ $rc -eq 0 ] || fail "$writer with 30 names taken exited $rc: $(cat "$work/plant.err")"
          passed=$((passed + 1))
        fi
      done
    done
  done
  echo "planted links and files: $cases cases (6 writers, links and files, 100 or 30 of the process's names and OUT.tmp taken): $refused refused cleanly, $passed written past them; no planted entry or other file changed"
}

# ---- 3. 20 concurrent saves to one OUT ----
concurrent() {
  local dir="$work/concurrent" ok=0 failed=0
  mkdir -p "$dir"
  local pids=()
  for i in $(seq 20); do
    "${save_cmd[@]}" -o "$dir/out.hdm" >/dev/null 2>"$dir/err.$i" &
    pids+=($!)
  done
  for p in "${pids[@]}"; do if wait "$p"; then ok=$((ok + 1)); else failed=$((failed + 1)); fi; done
  for i in $(seq 20); do [ ! -s "$dir/err.$i" ] || grep -q "hdm: error: .*out.hdm" "$dir/err.$i" ||
    fail "a concurrent save failed unclearly: $(cat "$dir/err.$i")"; done
  rm -f "$dir"/err.*
  [ "$(sha "$dir/out.hdm")" = "$sha_new" ] || fail "concurrent saves left a broken model"
  "$hdm" info "$dir/out.hdm" >/dev/null || fail "the model does not load"
  [ "$(ls -A "$dir")" = out.hdm ] || fail "left behind: $(ls -A "$dir")"
  echo "concurrent saves to one file: 20: $ok succeeded, $failed failed cleanly; OUT complete and loads, no temporary"
}

# ---- 4, 5. a full and a read-only file system, every writer ----
writers() {  # writers DIR: runs each writer into DIR; prints "name rc" lines, errors into DIR.err.*
  local d=$1
  "${save_cmd[@]}" -o "$d/m.hdm" >/dev/null 2>"$work/err.model"; echo "model $?"
  "${save_cmd[@]}" --forces "$d/f.csv" >/dev/null 2>"$work/err.csv"; echo "csv $?"
  "$hdm" export "$work/new.hdm" -o "$d/e.obj" >/dev/null 2>"$work/err.obj"; echo "obj $?"
  "$hdm" export "$work/new.hdm" -o "$d/e.ply" >/dev/null 2>"$work/err.ply"; echo "ply $?"
  "$hdm" export "$work/new.hdm" -o "$d/e.glb" >/dev/null 2>"$work/err.glb"; echo "glb $?"
  "$hdm" bake "$meshes/sphere.off" -o "$d/b.hdm" --slabs 300 --grid 16 --texels 8 --no-error-bound >/dev/null \
    2>"$work/err.bake"; echo "bake $?"
  "$hdm" feel "$work/old.hdm" --input "$meshes/sphere.off" --scenario press --trace "$d/t.csv" >/dev/null \
    2>"$work/err.trace"; echo "trace $?"
  if "$hdm" render "$work/old.hdm" -o "$work/probe.png" --size 64x48 >/dev/null 2>&1; then
    "$hdm" render "$work/new.hdm" -o "$d/v.png" --size 1600x1200 >/dev/null 2>"$work/err.png"; echo "png $?"
  fi
}

check_writers() {  # check_writers DIR WHAT REASON
  local d=$1 what=$2 reason=$3 n=0
  { echo old >"$d/e.obj"; } 2>/dev/null || true  # an old export to keep (the read-only one has it already)
  local before
  before=$(cd "$d" && ls -A | sort | tr '\n' ' ')
  while read -r name rc; do
    n=$((n + 1))
    [ "$rc" -eq 1 ] || fail "$what: the $name writer exited $rc"
    grep -qi "$reason" "$work/err.$name" || fail "$what: the $name writer's error is unclear: $(cat "$work/err.$name")"
  done < <(writers "$d")
  [ "$(cd "$d" && ls -A | sort | tr '\n' ' ')" = "$before" ] || fail "$what: left behind: $(ls -A "$d")"
  [ "$(cat "$d/e.obj")" = old ] || fail "$what: the old export was replaced"
  echo "$what: $n writers refused with a clear error ($reason), nothing new left"
}

full_and_readonly() {
  local full="$work/full" ro="$work/ro"
  mkdir -p "$full" "$ro"
  if mount -t tmpfs -o size=1m tmpfs "$full" 2>/dev/null; then
    mounts+=("$full")
    head -c 1032192 /dev/zero >"$full/ballast"  # leaves 16 KiB, less than any writer's output needs
    check_writers "$full" "full file system (a 1 MiB tmpfs)" "no space left"
  else
    (trap '' XFSZ; ulimit -f 16; check_writers "$full" "full file system (ulimit -f 16 KiB)" "too large") || exit 1
  fi
  echo old >"$ro/e.obj"
  if mount -t tmpfs -o size=4m tmpfs "$ro" 2>/dev/null; then
    mounts+=("$ro")
    echo old >"$ro/e.obj"
    mount -o remount,ro "$ro" || fail "cannot remount read-only"
    check_writers "$ro" "read-only file system (a tmpfs remounted ro)" "read-only file system"
  else
    chmod 555 "$ro"
    check_writers "$ro" "read-only directory (mode 555)" "permission denied"
  fi
}

# ---- 6. memory refusals ----
memory() {
  local t0 t1 ms
  t0=$(date +%s%N)
  "$hdm" bake "$meshes/sphere.off" -o "$work/x.hdm" --grid 256 --texels 16 --slabs 320 --no-error-bound \
    >/dev/null 2>"$work/err.mem" && fail "the 11 GB bake was not refused"
  t1=$(date +%s%N)
  ms=$(((t1 - t0) / 1000000))
  grep -q -- "--grid" "$work/err.mem" && grep -q -- "--texels" "$work/err.mem" || fail "the refusal names no options"
  [ "$ms" -lt 1000 ] || fail "the refusal took $ms ms"
  (ulimit -v 1048576; "$hdm" bake "$meshes/sphere.off" -o "$work/x.hdm" --max-memory 16) >/dev/null 2>"$work/err.mem"
  [ $? -eq 1 ] && grep -q -- "--max-memory" "$work/err.mem" || fail "the budget refusal: $(cat "$work/err.mem")"
  (ulimit -v 1048576; "$hdm" check "$work/old.hdm" --against "$meshes/sphere.off" --points 100000000 --max-memory 512) \
    >/dev/null 2>"$work/err.mem"
  [ $? -eq 1 ] && grep -q -- "--points" "$work/err.mem" || fail "the check refusal: $(cat "$work/err.mem")"
  echo "memory: the 11 GB bake refused in $ms ms naming --grid and --texels; a bake and a 1e8-point check refused by the budget under a 1 GiB address space"
}

# ---- 7. the bridge: a restarting driver, forged packets from another socket, a wrong secret ----
bridge() {
  local port=$((40000 + RANDOM % 20000)) key="$work/bridge.key" csv="$work/rec.csv"
  "$hdm" sculpt "$work/old.hdm" --fast --forces "$work/rec-all.csv" >/dev/null || fail "cannot record a trajectory"
  head -n 401 "$work/rec-all.csv" >"$csv"
  "$hdm" bridge "$work/old.hdm" --device "udp:$port" --secret-file "$key" --give-up-s 20 --json --no-realtime \
    >"$work/bridge.json" 2>"$work/bridge.err" &
  local hpid=$!
  python3 "$client" --udp $port "$csv" --secret-file "$key" --lockstep --stop-after 200 --no-end >"$work/c1.json" ||
    fail "the first driver failed"
  # The intruder: another socket sends the maximal sequence number and an END under guessed
  # session ids, and a hello with a wrong secret.
  python3 - "$port" <<'PY' || fail "the intruder could not send"
import os, socket, struct, sys
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
to = ("127.0.0.1", int(sys.argv[1]))
hdr = lambda kind, flags, seq, session: struct.pack("<IHHIIQQ", 0x424D4448, 2, kind, 96, flags, seq, session)
for session in (1, struct.unpack("<Q", os.urandom(8))[0]):
    s.sendto(hdr(1, 0, 2**64 - 1, session) + struct.pack("<d3d3dII", 0, 0.1, 0, 0, 0, 0, 0, 1, 0), to)
    s.sendto(hdr(1, 1, 2, session) + struct.pack("<d3d3dII", 0, 0.1, 0, 0, 0, 0, 0, 0, 0), to)
s.sendto(hdr(3, 0, 0, 99) + struct.pack("<I56sI", 20, b"not-the-secret-01234", 0), to)
PY
  HDM_BRIDGE_SECRET="a-wrong-secret-0123456789" python3 "$client" --udp $port "$csv" --lockstep --connect-timeout 0.2 \
    >/dev/null 2>&1 && fail "a driver with a wrong secret was served"
  python3 "$client" --udp $port "$csv" --secret-file "$key" --lockstep >"$work/c2.json" ||
    fail "the restarted driver was not served"
  wait $hpid || fail "hdm bridge failed: $(cat "$work/bridge.err")"
  python3 - "$work/c1.json" "$work/c2.json" "$work/bridge.json" <<'PY' || fail "the bridge's figures"
import json, sys
c1, c2, b = (json.load(open(p)) for p in sys.argv[1:4])
p = b["packets"]
assert c2["session_ms"] < 10, f"the restarted driver waited {c2['session_ms']:.2f} ms"
assert c2["answered"] == c2["packets"] and c2["lost"] == 0, c2
assert b["ended"] == "end packet", b["ended"]
assert p["wrong_session"] >= 4 and p["bad_secret"] >= 2 and p["sessions"] == 2, p
assert p["accepted"] == 200 + 400 + 1, p
print(f"bridge: restarted driver served after {c2['session_ms']:.2f} ms (first {c1['session_ms']:.2f} ms); "
      f"{p['wrong_session']} forged packets (maximal sequence, END) from another socket and "
      f"{p['bad_secret']} wrong secrets refused and counted; the session went on to its own END")
PY
}

# ---- 8. every command's bad option: exit 1 or 2 ----
exit_codes() {
  local n=0
  for cmd in bake sculpt info export render check feel bench subdivide bridge studio; do
    for bad in --no-such-option "--max-input-mb 0" "--json=maybe"; do
      # shellcheck disable=SC2086
      "$hdm" $cmd $bad >/dev/null 2>&1
      local rc=$?
      [ $rc -eq 1 ] || [ $rc -eq 2 ] || fail "hdm $cmd $bad exited $rc"
      n=$((n + 1))
    done
  done
  for args in "render $work/old.hdm -o $work/v.png --size 0x0" "render $work/old.hdm -o $work/v.png --view up" \
    "bake $meshes/sphere.off -o $work/b.hdm --grid 999" "check $work/old.hdm --against $meshes/sphere.off --points 5" \
    "sculpt $work/old.hdm --rate 0" "feel $work/old.hdm --scenario nope" "bridge $work/old.hdm --device tcp:1"; do
    # shellcheck disable=SC2086
    "$hdm" $args >/dev/null 2>&1
    local rc=$?
    [ $rc -eq 1 ] || [ $rc -eq 2 ] || fail "hdm $args exited $rc"
    n=$((n + 1))
  done
  echo "exit codes: $n bad command lines over 11 commands, each exit 1 or 2"
}

start=$(date +%s)
parts="${PARTS:-kill_saves kill_exports planted concurrent full_and_readonly memory bridge exit_codes}"
for part in $parts; do "$part"; done
echo "fault_injection: all promises held ($(($(date +%s) - start)) s)"
