#!/usr/bin/env bash
# Builds hdm's libFuzzer targets with clang (ASan, UBSan) in build-fuzz/ and runs each for a
# bounded time, two at a time; fails on any crash, sanitizer report, leak, timeout or
# out-of-memory. Findings are written to build-fuzz/artifacts/; reproduce one with
#   build-fuzz/fuzz/fuzz_ply build-fuzz/artifacts/ply-crash-...
#
# Usage: bash scripts/fuzz.sh [SECONDS_PER_FUZZER] [FUZZER...]   (default: 25 s, all eight)
# Needs scripts/setup.sh (clang, the small CGAL meshes it seeds from). When build/bin/hdm exists
# (scripts/build.sh), models baked from those meshes, their OBJ/PLY exports and a recorded
# trajectory are added to the seeds.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-25}"
shift || true
fuzzers=("$@")
[ ${#fuzzers[@]} -gt 0 ] || fuzzers=(obj ply off stl hdm script replay bridge)
out="$here/build-fuzz"
start=$(date +%s)

# -O1 and line tables (-g1), as in the ASan lane: libFuzzer's recommended level, a quicker build.
cmake -S "$here" -B "$out" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DHDM_O3=OFF \
  -DHDM_BUILD_FUZZERS=ON -DHDM_BUILD_APPS=OFF -DHDM_BUILD_TESTS=OFF -DHDM_BUILD_BENCH=OFF -DHDM_BUILD_PYTHON=OFF >/dev/null
cmake --build "$out" -j "$(nproc)" --target $(printf 'fuzz_%s ' "${fuzzers[@]}")
built=$(date +%s)

# ---- seeds: real files from CGAL's data (extracted by setup.sh) and what hdm makes of them ----
seeds="$out/seeds"
rm -rf "$seeds"
mkdir -p "$seeds"/{obj,ply,off,stl,hdm,script,replay,bridge}
meshes="$here/data/meshes"
seed() {  # seed FORMAT FILE...: copies the files that setup.sh extracted
  local format=$1
  shift
  for f in "$@"; do
    if [ -f "$meshes/$f" ]; then cp "$meshes/$f" "$seeds/$format/"; fi
  done
}
seed off tetrahedron.off triangle.off cube_quad.off cube_poly.off mesh_with_colors.off icosahedron.off sphere.off
seed ply colored_tetra.ply sphere.ply
seed stl sphere.stl
# Other readers' test files (Debian's assimp-testmodels), those small enough to mutate.
assimp=/usr/share/assimp/models
if [ -d "$assimp" ]; then
  for format in obj ply off stl; do
    find "$assimp/${format^^}" -maxdepth 1 -type f -size -32k \( -iname "*.$format" -o ! -name "*.*" \) \
      -exec cp {} "$seeds/$format/" \;
  done
fi
cp "$here"/data/scripts/*.json "$seeds/script/"
hdm="$here/build/bin/hdm"
derived_seeds() {
  local tmp="$out/seed-work"
  mkdir -p "$tmp"
  "$hdm" bake "$meshes/icosahedron.off" -o "$seeds/hdm/icosahedron.hdm" --slabs 20 --grid 2 --texels 2 --no-error-bound &&
    "$hdm" bake "$meshes/tetrahedron.off" -o "$seeds/hdm/tetrahedron.hdm" --slabs 4 --grid 3 --texels 1 --no-error-bound &&
    "$hdm" export "$seeds/hdm/icosahedron.hdm" -o "$seeds/obj/icosahedron.obj" &&
    "$hdm" export "$seeds/hdm/icosahedron.hdm" -o "$seeds/ply/icosahedron.ply" &&
    "$hdm" sculpt "$seeds/hdm/icosahedron.hdm" --script "$here/fuzz/corpus/script/two_strokes.json" --fast \
      --forces "$tmp/forces.csv" &&
    head -n 40 "$tmp/forces.csv" >"$seeds/replay/sculpt_forces.csv"
}
if [ -x "$hdm" ] && [ -f "$meshes/icosahedron.off" ]; then
  derived_seeds >/dev/null || echo "fuzz: could not make every seed with $hdm; going on with the others" >&2
  rm -f "$seeds"/obj/*.mtl "$seeds"/obj/*.png
else
  echo "fuzz: build/bin/hdm not built: seeding without baked models, exports and recordings" >&2
fi

# ---- run: two fuzzers at a time ----
run_one() {
  local name=$1
  mkdir -p "$out/corpus/$name" "$out/artifacts"
  # -timeout: one input taking longer is a hang; -rss_limit_mb / -malloc_limit_mb: an out-of-memory;
  # leaks are reported by LeakSanitizer at the end of each input that allocated.
  "$out/fuzz/fuzz_$name" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
    -max_len=32768 -print_final_stats=1 -dict="$here/fuzz/dict/$name.dict" \
    -artifact_prefix="$out/artifacts/$name-" \
    "$out/corpus/$name" "$here/fuzz/corpus/$name" "$seeds/$name" >"$out/fuzz_$name.log" 2>&1
}
pids=()
names=()
status=0
report() {
  local i=$1 rc=0
  wait "${pids[$i]}" || rc=$?
  local name=${names[$i]} log="$out/fuzz_${names[$i]}.log"
  local execs
  execs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  if [ $rc -eq 0 ]; then
    printf 'fuzz: %-7s %10s executions in %s s, no crash, leak, timeout or OOM\n' "$name" "$execs" "$seconds"
  else
    status=1
    printf 'fuzz: %-7s FAILED after %s executions (exit %d); log %s\n' "$name" "$execs" "$rc" "$log" >&2
    grep -E 'ERROR|SUMMARY|runtime error|Test unit written|Base64' "$log" | head -n 20 >&2 || true
  fi
}
jobs_max=$(nproc)
for name in "${fuzzers[@]}"; do
  run_one "$name" &
  pids+=($!)
  names+=("$name")
  if [ ${#pids[@]} -ge "$jobs_max" ]; then
    report 0
    pids=("${pids[@]:1}")
    names=("${names[@]:1}")
  fi
done
while [ ${#pids[@]} -gt 0 ]; do
  report 0
  pids=("${pids[@]:1}")
  names=("${names[@]:1}")
done
end=$(date +%s)
echo "fuzz: build $((built - start)) s, seeds and runs $((end - built)) s, total $((end - start)) s"
exit $status
