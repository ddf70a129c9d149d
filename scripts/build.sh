#!/usr/bin/env bash
# Configures and builds structmesh (Release, all cores) into build/ (or $BUILD_DIR).
# Extra arguments go to cmake's configure step, e.g. -DSTRUCTMESH_WERROR=ON.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build_dir=${BUILD_DIR:-$root/build}
cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="${BUILD_TYPE:-Release}" "$@"
cmake --build "$build_dir" -j "$(nproc)"
