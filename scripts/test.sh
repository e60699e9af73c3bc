#!/usr/bin/env bash
# Sets up (packages, models), checks the API reference (scripts/api_docs.sh: Doxygen, any warning
# fails), builds and runs every test with ctest, then the installed package (scripts/test_consumer.sh:
# install, build examples/consumer with find_package(hdm), run it), the ThreadSanitizer lane
# (scripts/test_tsan.sh: the concurrency stress test) and the fuzzing lane (scripts/fuzz.sh: every
# reader's libFuzzer target for HDM_FUZZ_SECONDS each, default 25; 0 skips).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/setup.sh"
bash "$here/scripts/api_docs.sh"  # seconds: fails before the build on an undocumented public symbol
bash "$here/scripts/build.sh"
(cd "$here/build" && ctest --output-on-failure -j 2)
bash "$here/scripts/test_consumer.sh"  # the installed package, as a find_package(hdm) user builds it
bash "$here/scripts/test_tsan.sh"      # the concurrency stress test under ThreadSanitizer
seconds="${HDM_FUZZ_SECONDS:-25}"
if [ "$seconds" != 0 ]; then bash "$here/scripts/fuzz.sh" "$seconds"; fi
