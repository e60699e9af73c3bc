#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer lane: builds the whole test suite, the hdm program
# and the studio with clang in build-asan/, all of it with ASan and the code under test with UBSan
# too (not the CGAL repair units nor the tests themselves), and runs ctest there. clang, not the
# main build's g++: its instrumented build takes about half the compiler CPU (1,438 s against
# about 2,680 s with g++ on a 2-core AMD EPYC; the largest CGAL unit 103 s against 158 s), and the
# sanitizers also check a second compiler's reading of the code. Any ASan report (heap or stack
# overflow, use after free, leak) or UBSan report (overflow, misaligned or null access,
# out-of-bounds index, invalid shift or cast: -fno-sanitize-recover=all) fails the test that made
# it. (The fuzzers have their own build: scripts/fuzz.sh.)
# The Python module is left out (an instrumented extension needs the runtime preloaded into the
# interpreter); the ThreadSanitizer lane is scripts/test_tsan.sh.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$here/build-asan"
start=$(date +%s)
flags="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
# -O1 everywhere (HDM_O3=OFF drops the library's -O3) and line tables only (-g1): the level the
# sanitizers recommend, and a quicker build (an instrumented library unit 43.9 -> 32.6 s without
# -O3; at -O2 -g the lane's build took 19 min against 11); reports still name the file and line.
# The CGAL repair units and the test code get ASan without UBSan (HDM_REPAIR_WITHOUT_UBSAN,
# src/CMakeLists.txt; HDM_TESTS_WITHOUT_UBSAN, tests/CMakeLists.txt): UBSan nearly doubles their
# build, while the library, hdm and the studio, the code under test, keep it.
cmake -S "$here" -B "$out" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DHDM_O3=OFF -DHDM_REPAIR_WITHOUT_UBSAN=ON -DHDM_TESTS_WITHOUT_UBSAN=ON \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DHDM_BUILD_APPS=ON -DHDM_BUILD_STUDIO=ON -DHDM_BUILD_TESTS=ON -DHDM_BUILD_BENCH=OFF -DHDM_BUILD_PYTHON=OFF >/dev/null
cmake --build "$out" -j "$(nproc)"
built=$(date +%s)
# Leaks inside Mesa's and X11's libraries (the studio's and the renderer's GL contexts) are theirs:
# suppressed by library name only (scripts/lsan.supp), never for hdm's own code.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:halt_on_error=1:hard_rss_limit_mb=4096:detect_stack_use_after_return=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$here/scripts/lsan.supp:print_suppressions=0"
export HDM_SANITIZED=1
gl='^studio_session$|^studio_burr$|^studio_bridge$|^studio_bridge_burr$|^RenderPng\.|^SlabRenderer\.'
# The corpus cases that take longest (seconds each in the main lane, minutes here; and
# b9_mesh peaks at 1.4 GB uninstrumented) run in the main lane only; knot1, fandisk and the
# b9.ply refusal run here too (remove_folds() has its unit tests here). So do the five real-model
# tests that took 16-45 s each here (the shell of bunny and armadillo at 150-5,000 slabs, the swept
# booleans against the exact one, the cow and triceratops bakes): the same code runs here on the
# smaller models of the other tests.
slow='^corpus\.(cow|elephant|femur|cheese|homer|b9_mesh)\.off$'
slow="$slow|^ShellTest\.RealModelsAreValidAndDisjointFrom150To5000Slabs$|^SweptEdit\.(CarvedGroove|AddedRidge)MatchesTheExactBoolean$"
slow="$slow|^ClosedSelfIntersection\.(Cow|Triceratops)BakesAtDefaultSettings$"
# Six more of 15-76 s each here, whose code the lighter tests of the same suites run on smaller
# inputs: decimation in parts with edge caps (EdgeCapsRefineTheirRegionAndNothingElse, and
# ALargeInputDecimatedInParts stay), the bake of a remeshed needle fan (RemeshIsotropic's test
# stays), the shell at its slab and grid extremes, the real-model bakes, boeing, and the tolerance
# loop's brute-force check (its two other real-model tests stay).
slow="$slow|^DecimateMeshTest\.EdgeCapsHoldThroughTheDecimationInParts$|^BakeInput\.NeedleFansAreBakedFromARemeshOfTheSameSurface$"
slow="$slow|^ShellTest\.SlabCountAndGridExtremes$|^BakeTest\.RealModelsBake$|^corpus\.boeing\.off$"
slow="$slow|^BakeToToleranceTest\.RefinesUntilTheBoundHoldsByBruteForce$"
# Three of the rigid burr's, 32-54 s each here: the studio's lockstep (the burr session of
# studio_burr run twice, to compare the runs), the allocation check of its session's ticks (the
# whole-session check stays) and the shaft-on-edge scenario (RigidTool.* and the drilling
# scenario run the same tool code here).
slow="$slow|^studio_lockstep$|^Realtime\.RigidToolSessionTicksDoNotAllocate$|^ToolScenario\.ShaftEdgeTorqueIsTheEdgeContactsLeverArmMoment$"
(cd "$out" && ctest --output-on-failure -j "$(nproc)" -E "^python\\.|$gl|$slow")
# The tests that open OpenGL (EGL or Xvfb): Mesa's drivers are dlopen'd and unloaded, so
# LeakSanitizer cannot name the module of their leaks, and its tracer has crashed at exit beside
# llvmpipe's threads; leak checking is off for these (ASan and UBSan stay on). Two at a time, as
# in the main lane (each studio test starts its own X server).
(cd "$out" && ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0" ctest --output-on-failure -j "$(nproc)" -R "$gl")
end=$(date +%s)
echo "asan: build $((built - start)) s, tests $((end - built)) s"
