#!/usr/bin/env bash
# cli_checks.sh CHECK HDM MESHES [HDM_STUDIO]: one of the program's promises (docs/reliability.md),
# checked through the hdm program. Exit 0: it holds; 1: it does not (the reason on stderr); 77: a
# fixture is missing (scripts/setup.sh extracts data/meshes).
set -uo pipefail
check=$1 hdm=$2 meshes=$3 studio=${4:-}
[ -f "$meshes/sphere.off" ] || { echo "no $meshes/sphere.off (run scripts/setup.sh)"; exit 77; }
tmp=$(mktemp -d)
trap 'chmod -R u+w "$tmp" 2>/dev/null; rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# expect CODE PATTERN COMMAND...: the command exits with CODE and its stderr holds PATTERN.
expect() {
  local code=$1 pattern=$2 rc=0
  shift 2
  "$@" >"$tmp/out" 2>"$tmp/err" || rc=$?
  [ "$rc" -eq "$code" ] || fail "exit $rc (expected $code): $* :: $(head -c 400 "$tmp/err")"
  grep -qF -- "$pattern" "$tmp/err" || fail "stderr lacks '$pattern': $* :: $(head -c 400 "$tmp/err")"
}
# The address-space limit the memory refusals run under (1 GiB: a command that allocated before
# refusing would die of it), except in an AddressSanitizer build, whose shadow memory alone is
# larger: there the refusal's message is checked without it.
if grep -q __asan_init "$hdm" 2>/dev/null; then limit=''; else limit='ulimit -v 1048576;'; fi
model() {  # a small model of the sphere
  [ -f "$tmp/m.hdm" ] || "$hdm" bake "$meshes/sphere.off" -o "$tmp/m.hdm" --slabs 40 --grid 4 --no-error-bound \
    >/dev/null || fail "cannot bake the fixture"
}

case "$check" in
output_is_never_the_input)
  cp "$meshes/sphere.off" "$tmp/in.off"
  ln "$tmp/in.off" "$tmp/hardlink.off"
  sum=$(sha256sum <"$tmp/in.off")
  expect 1 "is the input file" "$hdm" bake "$tmp/in.off" -o "$tmp/in.off"
  expect 1 "is the input file" "$hdm" bake "$tmp/in.off" -o "$tmp/../$(basename "$tmp")/./in.off"
  expect 1 "is the input file" "$hdm" bake "$tmp/in.off" -o "$tmp/hardlink.off"
  expect 1 "'.ply' is the extension of another format" "$hdm" bake "$tmp/in.off" -o "$tmp/new.ply"
  expect 1 "is the input file" "$hdm" subdivide "$tmp/in.off" -o "$tmp/hardlink.off"
  [ "$(sha256sum <"$tmp/in.off")" = "$sum" ] || fail "the input changed"
  [ ! -e "$tmp/new.ply" ] || fail "a model was written as new.ply"
  model
  cp "$tmp/m.hdm" "$tmp/m2.hdm"
  msum=$(sha256sum <"$tmp/m.hdm")
  expect 1 "is the input file" "$hdm" sculpt "$tmp/m.hdm" -o "$tmp/m.hdm" --fast
  expect 1 "'.obj' is the extension of another format" "$hdm" sculpt "$tmp/m.hdm" -o "$tmp/m.obj" --fast
  expect 1 "is the input file" "$hdm" sculpt "$tmp/m.hdm" --forces "$tmp/m.hdm" --fast
  expect 1 "is the input file" "$hdm" render "$tmp/m.hdm" -o "$tmp/m.hdm"
  expect 1 "'.stl' is the extension of another format" "$hdm" bridge "$tmp/m.hdm" --device udp:0 -o "$tmp/x.stl"
  if [ -n "$studio" ]; then  # refused before any window opens
    expect 1 "is the input file" "$studio" "$tmp/m.hdm" --script "$tmp/m2.hdm" --report "$tmp/m.hdm"
  fi
  [ "$(sha256sum <"$tmp/m.hdm")" = "$msum" ] || fail "the model changed"
  ;;
export_set_on_a_full_disk)
  model
  mkdir "$tmp/F"
  echo old >"$tmp/F/b.obj"
  # A file size limit stands in for a full file system here (scripts/fault_injection.sh fills a
  # real one): the OBJ's write fails; SIGXFSZ is ignored so the write returns the error.
  expect 1 "b.obj" bash -c "trap '' XFSZ; ulimit -f 8; exec \"\$0\" export \"\$1\" -o \"\$2\"" \
    "$hdm" "$tmp/m.hdm" "$tmp/F/b.obj"
  [ "$(cat "$tmp/F/b.obj")" = old ] || fail "the old OBJ was replaced"
  [ "$(ls -A "$tmp/F")" = b.obj ] || fail "left behind: $(ls -A "$tmp/F" | tr '\n' ' ')"
  "$hdm" export "$tmp/m.hdm" -o "$tmp/F/b.obj" >/dev/null || fail "the export without the limit failed"
  [ "$(ls -A "$tmp/F" | tr '\n' ' ')" = "b.mtl b.obj b.png " ] || fail "the export wrote $(ls -A "$tmp/F")"
  ;;
memory_refused_before_allocation)
  model
  # Each refusal under a 1 GiB address space: had the command allocated first, it would die of it.
  expect 1 "--max-memory" bash -c "$limit"' exec "$@"' _ "$hdm" bake "$meshes/sphere.off" -o "$tmp/b.hdm" \
    --max-memory 16
  grep -q "MiB" "$tmp/err" || fail "the refusal gives no estimate"
  expect 1 "--points" bash -c "$limit"' exec "$@"' _ "$hdm" check "$tmp/m.hdm" --against "$meshes/sphere.off" \
    --points 100000000 --max-memory 512
  grep -q -- "--max-memory" "$tmp/err" || fail "the check refusal does not name --max-memory"
  # A script of a very slow stroke: millions of ticks.
  cat >"$tmp/slow.json" <<'JSON'
{"strokes": [{"tool": "carve", "from": [0.2, 0.5, 1.0], "to": [0.8, 0.5, 1.0], "speed_mm_s": 0.01}]}
JSON
  expect 1 "--max-memory" bash -c "$limit"' exec "$@"' _ "$hdm" sculpt "$tmp/m.hdm" --script "$tmp/slow.json" \
    --fast --max-memory 64
  grep -q "ticks" "$tmp/err" || fail "the sculpt refusal does not say how many ticks"
  [ ! -e "$tmp/b.hdm" ] || fail "a refused bake wrote its output"
  ;;
format_limits_at_parse_time)
  # 320 slabs of 4,097·4,098/2 texel grid points: more than a .hdm file holds (once 36 s and 11 GB).
  expect 1 "--texels" bash -c "$limit"' exec "$@"' _ "$hdm" bake "$meshes/sphere.off" -o "$tmp/b.hdm" \
    --grid 256 --texels 16 --slabs 320 --no-error-bound
  grep -q -- "--grid" "$tmp/err" || fail "the refusal does not name --grid"
  ;;
unknown_script_key)
  model
  cat >"$tmp/typo.json" <<'JSON'
{"strokes": [{"tool": "carve", "from": [0.2, 0.5, 1.0], "to": [0.8, 0.5, 1.0], "radus_mm": 2}]}
JSON
  expect 1 "unknown key 'radus_mm' (did you mean 'radius_mm'?)" "$hdm" sculpt "$tmp/m.hdm" --script "$tmp/typo.json" --fast
  grep -q "strokes\[0\]" "$tmp/err" || fail "the error does not say where the key is"
  echo '{"strokes": [{"undo": 1}], "hand_stifness_n_per_m": 100}' >"$tmp/top.json"
  expect 1 "did you mean 'hand_stiffness_n_per_m'" "$hdm" sculpt "$tmp/m.hdm" --script "$tmp/top.json" --fast
  ;;
coordinate_out_of_range)
  printf 'OFF\n4 4 0\n0 0 0\n1e300 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$tmp/huge.off"
  expect 1 "out of range" "$hdm" bake "$tmp/huge.off" -o "$tmp/h.hdm"
  ! grep -q "non-finite" "$tmp/err" || fail "1e300 was called non-finite"
  printf 'OFF\n4 4 0\n0 0 0\nnan 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$tmp/nan.off"
  expect 1 "non-finite" "$hdm" bake "$tmp/nan.off" -o "$tmp/h.hdm"
  ;;
exit_codes)
  model
  # 2: usage (an unknown option, a value its validator refuses, a missing argument); 1: bad input.
  for cmd in bake sculpt info export render check feel bench subdivide bridge studio; do
    expect 2 "" "$hdm" "$cmd" --no-such-option
  done
  expect 2 "" "$hdm"
  expect 2 "" "$hdm" no-such-command
  expect 2 "" "$hdm" bake "$meshes/sphere.off"
  expect 2 "size" "$hdm" render "$tmp/m.hdm" -o "$tmp/v.png" --size 0x0
  expect 2 "view" "$hdm" render "$tmp/m.hdm" -o "$tmp/v.png" --view up
  expect 2 "" "$hdm" bake "$meshes/sphere.off" -o "$tmp/b.hdm" --grid 0
  expect 2 "" "$hdm" check "$tmp/m.hdm" --against "$meshes/sphere.off" --points 1
  expect 1 "no-such-file.off" "$hdm" bake "$tmp/no-such-file.off" -o "$tmp/b.hdm"
  expect 1 "" "$hdm" info "$meshes/sphere.off"
  "$hdm" --help >/dev/null || fail "--help exits $?"
  "$hdm" info "$tmp/m.hdm" >/dev/null || fail "info exits $?"
  if [ -n "$studio" ]; then
    expect 2 "" "$studio" --no-such-option
    expect 2 "size" "$studio" "$tmp/m.hdm" --size big
    expect 2 "lod" "$studio" "$tmp/m.hdm" --lod nine
  fi
  ;;
*)
  fail "unknown check $check"
  ;;
esac
echo "ok: $check"
