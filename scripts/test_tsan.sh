#!/usr/bin/env bash
# ThreadSanitizer lane: builds the concurrency stress test alone (its runtime sources, no bake or
# file-format libraries) with -fsanitize=thread in build-tsan/ and runs it. Any data race fails it.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cmake -S "$here" -B "$here/build-tsan" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHDM_TSAN=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
  -DHDM_BUILD_APPS=OFF -DHDM_BUILD_BENCH=OFF -DHDM_BUILD_PYTHON=OFF \
  -DCMAKE_CXX_FLAGS="-fsanitize=thread -fno-omit-frame-pointer" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" >/dev/null
cmake --build "$here/build-tsan" --target concurrency_tests -j "$(nproc)"
TSAN_OPTIONS="halt_on_error=1 exitcode=66 second_deadlock_stack=1" "$here/build-tsan/tests/session/concurrency_tests"
