#!/usr/bin/env bash
# Sets up (packages, models), builds and runs every test with ctest, then the ThreadSanitizer lane.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/setup.sh"
bash "$here/scripts/build.sh"
(cd "$here/build" && ctest --output-on-failure -j 2)
bash "$here/scripts/test_tsan.sh"  # the concurrency stress test under ThreadSanitizer
