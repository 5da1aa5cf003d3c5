#!/usr/bin/env bash
# Installs every Debian 12 package hlod needs to build, test and plot,
# and the npm packages of tests/export (npm ci). Idempotent: when everything is present it prints
# nothing and touches nothing.
# --slurm also installs Slurm and MUNGE, for the opt-in one-node Slurm test of the workflow
# (tests/workflow/test_slurm.sh, HLOD_SLURM_TEST=1; README "Beyond one machine"); the default
# path leaves them out (they pull about 89 packages with Snakemake, ~3 min here).
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config ninja-build
  libopenmesh-dev        # OpenMesh: mesh data structure + Decimater (alternate simplifier)
  libopenimageio-dev     # OpenImageIO: texture formats other than JPEG and PNG, in the plugin hlod_oiio.so (loaded on demand)
  openimageio-tools python3-imath  # their CMake configs reference /usr/bin/iconvert and libPyImath: configure fails without them
  libcgal-dev libeigen3-dev  # CGAL: scan holes triangulated (triangulate_hole_polyline, fill_holes.cpp)
  libdraco-dev           # Draco: geometry compression of node blobs
  libtinygltf-dev nlohmann-json3-dev libstb-dev  # glTF input; JSON output
  libmeshoptimizer-dev   # meshoptimizer: fast quadric simplification with border locking
  libtinyobjloader-dev   # tinyobjloader: OBJ + MTL input (many materials, photogrammetry atlases)
  libtbb-dev             # TBB: parallel blocks in the pipeline
  libcli11-dev           # CLI11: git-style subcommands and --help
  libxxhash-dev          # xxHash: XXH3-64 checksums of skeleton and blobs
  libjpeg62-turbo-dev    # libjpeg-turbo: JPEG textures read and written (node textures with optimised Huffman tables)
  libpng-dev             # libpng: PNG textures read row by row and written, without OpenImageIO's ~122 MiB of libraries
  zlib1g-dev             # zlib: CRC-32 of the entries of a .3tz archive (hlod export tiles --3tz)
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libglfw3-dev  # OpenGL renderer (EGL headless / GLFW)
  libgtest-dev libgmock-dev libbenchmark-dev  # tests and benchmarks
  clang libclang-rt-14-dev  # libFuzzer targets and sanitizer runtime
  gnuplot-nox            # thesis Figure 6.x plots
  xvfb xdotool           # `hlod view` window test under a virtual X server
  nodejs chromium        # `hlod export tiles` checks: gltf-validator and CesiumJS in headless chromium (tests/export/)
  snakemake              # the split -> shards -> merge workflow (scripts/workflow/Snakefile) and its test
  time                   # GNU time: CPU-s and peak RSS in the benchmark scripts (scripts/bench-*.sh)
)
[ "${1:-}" = --slurm ] && PACKAGES+=(slurm-wlm munge)  # slurmctld, slurmd, sbatch; munged authenticates them
# Debian's nodejs leaves npm to a package of its own; NodeSource's nodejs brings npm and conflicts with it.
command -v npm >/dev/null || PACKAGES+=(npm)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -ne 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# The npm packages of the export checks, pinned in tests/export/package-lock.json: `npm ci` when
# node_modules was not installed from this very lock file (a copy of it marks the install).
export_dir="$(dirname "$0")/../tests/export"
if ! cmp -s "$export_dir/package-lock.json" "$export_dir/node_modules/.hlod-package-lock.json"; then
  echo "install-deps: npm ci in tests/export"
  (cd "$export_dir" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
  cp "$export_dir/package-lock.json" "$export_dir/node_modules/.hlod-package-lock.json"
fi
