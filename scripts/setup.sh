#!/usr/bin/env bash
# Installs every Debian package hdm needs and extracts the real models it uses
# from Debian's libcgal-demo data archive into data/meshes/ (ignored by git): the four
# models of the docs, and small files in every format the readers' tests and fuzzers start from.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

packages=(cmake ninja-build g++ pkg-config
  libeigen3-dev libtbb-dev libembree-dev
  libassimp-dev libtinygltf-dev libstb-dev nlohmann-json3-dev libcli11-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libegl-dev libgl-dev libgl1-mesa-dri
  libcgal-dev libcgal-demo assimp-testmodels gnuplot-nox
  libglfw3-dev libimgui-dev xvfb xauth
  clang libclang-rt-14-dev
  pybind11-dev python3-dev python3-numpy python3-pytest
  doxygen)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  echo "setup: installing ${missing[*]}" >&2
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

archive=/usr/share/doc/libcgal-dev/data.tar.gz
models=(bunny00.off armadillo.off refined_elephant.off lion-head.off cheese.off knot1.off
  sphere.off sphere.ply sphere.stl colored_tetra.ply mesh_with_colors.off cube_poly.off
  tetrahedron.off cube_quad.off icosahedron.off triangle.off blobby.off bones.off cow.off triceratops.off
  b9.ply)
mkdir -p "$here/data/meshes"
need=()
for m in "${models[@]}"; do [ -s "$here/data/meshes/$m" ] || need+=("data/meshes/$m"); done
if [ ${#need[@]} -gt 0 ]; then
  [ -f "$archive" ] || { echo "setup: $archive not found (package libcgal-demo)" >&2; exit 1; }
  tar -xzf "$archive" -C "$here/data/meshes" --strip-components=2 "${need[@]}"
fi
