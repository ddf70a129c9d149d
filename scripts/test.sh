#!/usr/bin/env bash
# Installs what is missing, builds (Release, warnings as errors) and runs the whole test suite.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
# OpenBLAS pinned to its AVX2 kernels where the CPU has them (why: in the script).
source "$root/scripts/pin-blas.sh"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" -DSTRUCTMESH_WERROR=ON
cd "${BUILD_DIR:-$root/build}"
ctest --output-on-failure -j "$(nproc)" --timeout 600
