#!/usr/bin/env bash
# Installs every Debian 12 package hlod needs to build, test and plot.
# Idempotent: when everything is present it prints nothing and touches nothing.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config ninja-build
  libopenmesh-dev        # OpenMesh: mesh data structure + Decimater (alternate simplifier)
  libopenimageio-dev     # OpenImageIO: image read/write/resize
  openimageio-tools python3-imath  # their CMake configs reference /usr/bin/iconvert and libPyImath: configure fails without them
  libcgal-dev libeigen3-dev  # CGAL: AABB-tree distance queries for geometric error
  libdraco-dev           # Draco: geometry compression of node blobs
  libtinygltf-dev nlohmann-json3-dev libstb-dev  # glTF input; JSON output
  libmeshoptimizer-dev   # meshoptimizer: fast quadric simplification with border locking
  libtinyobjloader-dev   # tinyobjloader: OBJ + MTL input (many materials, photogrammetry atlases)
  libtbb-dev             # TBB: parallel blocks in the pipeline
  libcli11-dev           # CLI11: git-style subcommands and --help
  libxxhash-dev          # xxHash: XXH3-64 checksums of skeleton and blobs
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libglfw3-dev  # OpenGL renderer (EGL headless / GLFW)
  libgtest-dev libgmock-dev libbenchmark-dev  # tests and benchmarks
  clang libclang-rt-14-dev  # libFuzzer targets and sanitizer runtime
  gnuplot-nox            # thesis Figure 6.x plots
  xvfb xdotool           # `hlod view` window test under a virtual X server
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install-deps: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
