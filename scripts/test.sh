#!/usr/bin/env bash
# Sets up (packages, models), builds and runs every test with ctest, then the ThreadSanitizer lane
# (scripts/test_tsan.sh: the concurrency stress test) and the fuzzing lane (scripts/fuzz.sh: every
# reader's libFuzzer target for HDM_FUZZ_SECONDS each, default 25; 0 skips).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/setup.sh"
bash "$here/scripts/build.sh"
(cd "$here/build" && ctest --output-on-failure -j 2)
bash "$here/scripts/test_tsan.sh"  # the concurrency stress test under ThreadSanitizer
seconds="${HDM_FUZZ_SECONDS:-25}"
if [ "$seconds" != 0 ]; then bash "$here/scripts/fuzz.sh" "$seconds"; fi
