#!/usr/bin/env bash
# Sets up (packages, models), checks the API reference (scripts/api_docs.sh: Doxygen, any warning
# fails), builds and runs every test with ctest, then the installed package (scripts/test_consumer.sh:
# install, build examples/consumer with find_package(hdm), run it), the fault-injection lane
# (scripts/fault_injection.sh: docs/reliability.md's promises under kills, planted links, full and
# read-only file systems and a hostile bridge peer), the ThreadSanitizer lane
# (scripts/test_tsan.sh: the concurrency stress test), the AddressSanitizer + UBSan lane
# (scripts/test_asan.sh: the whole suite; HDM_ASAN=0 skips it) and the fuzzing lane (scripts/fuzz.sh:
# every reader's libFuzzer target for HDM_FUZZ_SECONDS each, default 20; 0 skips), printing each
# lane's time at the end.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
times=()
lane() {  # lane NAME COMMAND...: runs one step and keeps its time
  local name=$1 t0
  shift
  t0=$(date +%s)
  "$@"
  times+=("$name $(($(date +%s) - t0)) s")
}
lane setup bash "$here/scripts/setup.sh"
lane api-docs bash "$here/scripts/api_docs.sh"  # seconds: fails before the build on an undocumented public symbol
lane build bash "$here/scripts/build.sh"
lane ctest bash -c "cd '$here/build' && ctest --output-on-failure -j 2"
lane fault-injection bash "$here/scripts/fault_injection.sh"  # kills, planted links, full disks, the bridge (docs/reliability.md)
lane consumer bash "$here/scripts/test_consumer.sh"  # the installed package, as a find_package(hdm) user builds it
lane tsan bash "$here/scripts/test_tsan.sh"          # the concurrency stress test under ThreadSanitizer
if [ "${HDM_ASAN:-1}" != 0 ]; then lane asan-ubsan bash "$here/scripts/test_asan.sh"; fi
seconds="${HDM_FUZZ_SECONDS:-20}"
if [ "$seconds" != 0 ]; then lane fuzz bash "$here/scripts/fuzz.sh" "$seconds"; fi
printf 'lane %s\n' "${times[@]}"
