#!/usr/bin/env bash
# The installed package as a user gets it: installs build/ into a temporary prefix, configures and
# builds examples/consumer against it with find_package(hdm), and runs it (bake a sphere, press a
# probe into it through the proxy). Fails when a detail/ header is installed, when the consumer of
# hdm::core and hdm::io sees Embree, TBB or CGAL on its compile or link line, or when a program fails.
# Run after scripts/build.sh; scripts/test.sh runs it.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"

cmake --install "$here/build" --prefix "$prefix" >/dev/null
for f in lib/cmake/hdm/hdmConfig.cmake lib/cmake/hdm/hdmConfigVersion.cmake include/hdm/query/slab_query.h \
  lib/libhdm_core.a bin/hdm; do
  [ -e "$prefix/$f" ] || { echo "test_consumer: $f not installed" >&2; exit 1; }
done
if [ -e "$prefix/include/hdm/query/detail" ]; then
  echo "test_consumer: include/hdm/query/detail installed (internal headers)" >&2; exit 1
fi

# hdm::core's exported link interface: Eigen and threads, nothing else (hdm's libraries are static,
# so even a private dependency would reach every consumer's link line).
core_links=$(grep -h INTERFACE_LINK_LIBRARIES "$prefix/lib/cmake/hdm/hdm-core-targets.cmake" | cut -d'"' -f2 |
  tr ';' '\n' | grep -v 'LINK_ONLY:>$' | tr '\n' ' ')
if [ "$core_links" != "Eigen3::Eigen Threads::Threads " ]; then
  echo "test_consumer: hdm::core exports more than Eigen and Threads: $core_links" >&2; exit 1
fi

cmake -S "$here/examples/consumer" -B "$work/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_EXPORT_COMPILE_COMMANDS=ON >/dev/null
cmake --build "$work/build" >/dev/null

# What a consumer of hdm::core (+ hdm::io) gets: compile line and link line of press_model.
compile_line=$(/usr/bin/python3 -c 'import json,sys
for e in json.load(open(sys.argv[1])):
    if e["file"].endswith("press_model.cpp"): print(e["command"])' "$work/build/compile_commands.json")
link_line=$(awk '/^build press_model:/{f=1} f&&/LINK_LIBRARIES/{print; exit}' "$work/build/build.ninja")
echo "test_consumer: press_model (hdm::core, hdm::io) compiles with: $(echo "$compile_line" | grep -o -- '-[DI][^ ]*\|-isystem [^ ]*' | tr '\n' ' ')"
echo "test_consumer: and links: ${link_line#*= }"
if echo "$compile_line $link_line" | grep -qiE 'embree|tbb|cgal|gmp|mpfr'; then
  echo "test_consumer: Embree, TBB or CGAL on the line of a hdm::core consumer" >&2; exit 1
fi

"$work/build/bake_mesh" "$here/data/meshes/sphere.off" "$work/sphere.hdm"
"$work/build/press_model" "$work/sphere.hdm" | tail -n 3
"$prefix/bin/hdm" info "$work/sphere.hdm" >/dev/null
echo "test_consumer: the installed package builds and runs"
