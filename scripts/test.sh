#!/usr/bin/env bash
# Sets up (packages, models), builds and runs every test with ctest, then the ThreadSanitizer lane
# (scripts/test_tsan.sh: the concurrency stress test), the AddressSanitizer + UBSan lane
# (scripts/test_asan.sh: the whole suite with clang; HDM_ASAN=0 skips) and the fuzzing lane
# (scripts/fuzz.sh: every reader's libFuzzer target for HDM_FUZZ_SECONDS each, default 25; 0 skips),
# printing each lane's time.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
lane() {  # lane NAME COMMAND...: runs a lane and prints its time
  local name=$1 t0
  shift
  t0=$(date +%s)
  "$@"
  echo "lane $name: $(($(date +%s) - t0)) s" | tee -a "$here/build/lanes.txt"
}
bash "$here/scripts/setup.sh"
bash "$here/scripts/build.sh"
: >"$here/build/lanes.txt"
lane tests bash -c "cd '$here/build' && ctest --output-on-failure -j 2"
lane tsan bash "$here/scripts/test_tsan.sh"  # the concurrency stress test under ThreadSanitizer
if [ "${HDM_ASAN:-1}" != 0 ]; then lane asan-ubsan bash "$here/scripts/test_asan.sh"; fi
seconds="${HDM_FUZZ_SECONDS:-25}"
if [ "$seconds" != 0 ]; then lane fuzz bash "$here/scripts/fuzz.sh" "$seconds"; fi
cat "$here/build/lanes.txt"
