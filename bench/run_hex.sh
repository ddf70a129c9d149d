#!/usr/bin/env bash
# Runs the polycube hex meshing benchmark (chapter 5: Table 5.2's measures and Table 5.1's
# stage times at the dissertation's hex counts) and stores the Markdown in bench/results/hex.md.
# With --untangle-map: the same with `structmesh hex --untangle-map` (the volumetric map's joint
# untangling), into bench/results/hex_untangle_map.md.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
# OpenBLAS pinned to its AVX2 kernels where the CPU has them (why: in the script).
source "$root/scripts/pin-blas.sh"
"$root/scripts/build.sh" >/dev/null
data=${STRUCTMESH_DATA:-$root/../shared/data}
bin="${BUILD_DIR:-$root/build}/bin"
result="$root/bench/results/hex.md"
title="Polycube hex meshing benchmark (issue 6, dissertation ch. 5)"
untangle=0
if [[ "${1:-}" == "--untangle-map" ]]; then
  result="$root/bench/results/hex_untangle_map.md"
  title="$title, with --untangle-map"
  untangle=1
fi
{
  echo "# $title"
  echo
  if [[ $untangle == 1 ]]; then
    echo "The same run as [hex.md](hex.md) with the opt-in joint untangling of the volumetric map"
    echo "(\`--untangle-map\`, \`untangle_tet_map()\`): the flipped-tets column gains its count, and the"
    echo "times include it. It is off by default for its cost (docs/design/hex.md)."
    echo
  fi
  echo "Measured $(date -u +%Y-%m-%d) on this machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo)," \
       "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'). One run each; times in seconds, wall clock."
  cat "$root/bench/hex/notes.md"
  echo
  BENCH_HEX_UNTANGLE_MAP=$untangle "$bin/bench_hex" "$data" 2>/dev/null
} >"$result.tmp"
mv "$result.tmp" "$result"
echo "wrote $result"
