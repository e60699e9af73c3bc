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
  expect 2 "shaft_edge and drill_layers" "$hdm" feel --scenario press
  expect 1 "builds its own block" "$hdm" feel "$tmp/m.hdm" --scenario slot
  expect 1 "--mode rigid" "$hdm" feel "$tmp/m.hdm" --scenario press --mode rigid
  expect 1 "(mode sphere) only" "$hdm" feel "$tmp/m.hdm" --scenario press --radius 0.1
  expect 1 "render mode 'spherical'" "$hdm" feel "$tmp/m.hdm" --scenario press --mode spherical
  "$hdm" --help >/dev/null || fail "--help exits $?"
  "$hdm" info "$tmp/m.hdm" >/dev/null || fail "info exits $?"
  if [ -n "$studio" ]; then
    expect 2 "" "$studio" --no-such-option
    expect 2 "size" "$studio" "$tmp/m.hdm" --size big
    expect 2 "lod" "$studio" "$tmp/m.hdm" --lod nine
  fi
  ;;
scale_free)
  # A mesh scaled by 2^k (exact in binary floating point) bakes to the same model, scaled: every
  # `hdm check` figure is equal. Scaled by powers of ten, from 1e-12 to 1e12, the input's decimal
  # rounding (1e-16 of a coordinate) is the only difference, and it can tip a choice of the bake:
  # local refinement acts on the points beyond the bound and on equal-cost collapses of a
  # symmetric part, so one point tipped across refines another handful of slabs. Then: the same
  # grid, slab count and samples within 10 %, every fidelity figure within the bound (0.2 % max,
  # 0.02 % RMS of the diagonal) and within 0.05 % / 0.005 % of the figure at scale 1, and at most
  # 0.5 % of the 20,000 random contact points judged differently. Outside the float range the
  # input is refused, naming the scale. The bunny runs in the uninstrumented build only.
  scaled() {  # scaled IN OUT FACTOR: an OFF file with every coordinate times FACTOR
    python3 - "$@" <<'PY'
import sys
src, dst, k = sys.argv[1], sys.argv[2], float(sys.argv[3])
lines = [l for l in open(src) if l.strip() and not l.lstrip().startswith("#")]
assert lines[0].strip() == "OFF"
nv = int(lines[1].split()[0])
with open(dst, "w") as f:
    f.write("OFF\n" + lines[1])
    for l in lines[2:2 + nv]:
        t = l.split()
        f.write(" ".join("%.17g" % (float(x) * k) for x in t[:3]) + " " + " ".join(t[3:]) + "\n")
    f.writelines(lines[2 + nv:])
PY
  }
  meshes_to_try=(sphere.off)
  grep -q __asan_init "$hdm" 2>/dev/null || meshes_to_try+=(bunny00.off)
  scales="1 0x1p-40 0x1p-20 0x1p20 0x1p40 1e-12 1e-6 1e6 1e12"
  for mesh in "${meshes_to_try[@]}"; do
    [ -f "$meshes/$mesh" ] || { echo "no $meshes/$mesh (run scripts/setup.sh)"; exit 77; }
    for k in $scales; do
      scaled "$meshes/$mesh" "$tmp/s$k.off" "$(python3 -c "print(repr(float.fromhex('$k') if '0x' in '$k' else float('$k')))")" ||
        fail "cannot scale $mesh"
      "$hdm" bake "$tmp/s$k.off" -o "$tmp/s$k.hdm" >"$tmp/bake$k.txt" 2>"$tmp/err" ||
        fail "bake of $mesh at scale $k exits $?: $(head -c 400 "$tmp/err")"
      "$hdm" check "$tmp/s$k.hdm" --against "$tmp/s$k.off" --points 20000 --json >"$tmp/check$k.json" ||
        fail "check of $mesh at scale $k exits $?"
    done
    python3 - "$tmp" "$mesh" $scales <<'PY' || fail "$mesh differs across scales"
import json, sys
tmp, mesh, scales = sys.argv[1], sys.argv[2], sys.argv[3:]
runs = {k: json.load(open("%s/check%s.json" % (tmp, k))) for k in scales}
ref = runs["1"]
bad = []
for k, r in runs.items():
    exact = k.startswith("0x")  # a power of two: every figure equal
    tol = {"rms": 0.0, "max": 0.0, "depth": 0.0, "points": 0, "count": 0.0} if exact else \
        {"rms": 5e-3, "max": 5e-2, "depth": 5e-2, "points": 100, "count": 0.1}
    for key in ["slabs", "grid", "invalid_slabs", "overlapping_pairs", "samples"]:
        if abs(r[key] - ref[key]) > (0 if key in ("grid", "invalid_slabs", "overlapping_pairs") else tol["count"]) * ref[key]:
            bad.append("%s at %s: %s %s, at 1: %s" % (mesh, k, key, r[key], ref[key]))
    for key, v in r["fidelity"].items():
        is_max = key.startswith("max")
        if abs(v - ref["fidelity"][key]) > tol["max" if is_max else "rms"] or v > (0.2 if is_max else 0.02):
            bad.append("%s at %s: fidelity %s %.6f%%, at 1: %.6f%%" % (mesh, k, key, v, ref["fidelity"][key]))
    c, c0 = r["contact"], ref["contact"]
    if round(abs(c["agreement"] - c0["agreement"]) * c0["points"]) > tol["points"]:
        bad.append("%s at %s: agreement %.6f, at 1: %.6f (of %d points)" % (mesh, k, c["agreement"], c0["agreement"], c0["points"]))
    for key in ["depth_rms_pct", "depth_max_pct"]:
        if abs(c[key] - c0[key]) > tol["depth"]:
            bad.append("%s at %s: %s %.6f, at 1: %.6f" % (mesh, k, key, c[key], c0[key]))
print("\n".join(bad), file=sys.stderr)
sys.exit(1 if bad else 0)
PY
  done
  scaled "$meshes/sphere.off" "$tmp/tiny.off" 1e-35
  expect 1 "tiny.off: the bounding-box diagonal is" "$hdm" bake "$tmp/tiny.off" -o "$tmp/tiny.hdm"
  scaled "$meshes/sphere.off" "$tmp/huge.off" 1e35
  expect 1 "huge.off: the bounding-box diagonal is" "$hdm" bake "$tmp/huge.off" -o "$tmp/huge.hdm"
  [ ! -e "$tmp/tiny.hdm" ] && [ ! -e "$tmp/huge.hdm" ] || fail "a refused bake wrote a model"
  ;;
*)
  fail "unknown check $check"
  ;;
esac
echo "ok: $check"
