#!/usr/bin/env bash
# Runs the foundation benchmark and stores its Markdown table in bench/results/foundation.md.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh" >/dev/null
data=${STRUCTMESH_DATA:-$root/../shared/data}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
result="$root/bench/results/foundation.md"
{
  echo "# Foundation benchmark"
  echo
  echo "Measured $(date -u +%Y-%m-%d) on this machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo)," \
       "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'). Best of 3 runs unless noted; times in seconds."
  echo
  "${BUILD_DIR:-$root/build}/bin/bench_foundation" "$data" "$work" "${GRID:-100}"
  echo
  echo "## Anchor: VTK 9.1 vtkMeshQuality (Verdict) on the same files"
  echo
  echo "| file | cells | vtkMeshQuality time (s) | SJ min |"
  echo "|---|---|---|---|"
  /usr/bin/python3 "$root/bench/foundation/vtk_quality.py" "$work/hex_grid.vtu" "$work/quad_grid.vtu"
} | tee "$result.tmp"
mv "$result.tmp" "$result"
