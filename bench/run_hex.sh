#!/usr/bin/env bash
# Runs the polycube hex meshing benchmark (chapter 5: Table 5.2's measures and Table 5.1's
# stage times at the dissertation's hex counts) and stores the Markdown in bench/results/hex.md.
# With --untangle-map: the same with `structmesh hex --smooth-surface-map --untangle-map` (the
# surface map's distortion smoothed before the first volumetric map, the joint untangling over
# 3, 6 and 12 rings and on the unmerged polycube's map too), into
# bench/results/hex_untangle_map.md.
# With --unseen: the built-in solids (solids.hpp, `structmesh generate SOLID`), made from
# formulas and never used to tune the pipeline, at 10k hexes with default settings, into
# bench/results/hex_unseen.md (their surfaces are written to out/unseen_shapes/ as OBJ).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
# OpenBLAS pinned to its AVX2 kernels where the CPU has them (why: in the script).
source "$root/scripts/pin-blas.sh"
"$root/scripts/build.sh" >/dev/null
data=${STRUCTMESH_DATA:-$root/../shared/data}
bin="${BUILD_DIR:-$root/build}/bin"
result="$root/bench/results/hex.md"
if [[ "${1:-}" == "--unseen" ]]; then
  result="$root/bench/results/hex_unseen.md"
  {
    echo "# Polycube hex meshing on shapes it was never tuned on (issue 6)"
    echo
    echo "Measured $(date -u +%Y-%m-%d) on this machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo)," \
         "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'). One run each; times in seconds, wall clock."
    cat "$root/bench/hex/unseen_notes.md"
    echo
    "$bin/bench_hex" --unseen "$root/out/unseen_shapes" 2>/dev/null
  } >"$result.tmp"
  mv "$result.tmp" "$result"
  echo "wrote $result"
  exit 0
fi
title="Polycube hex meshing benchmark (issue 6, dissertation ch. 5)"
untangle=0
if [[ "${1:-}" == "--untangle-map" ]]; then
  result="$root/bench/results/hex_untangle_map.md"
  title="$title, with --smooth-surface-map --untangle-map"
  untangle=1
fi
{
  echo "# $title"
  echo
  if [[ $untangle == 1 ]]; then
    echo "The same run as [hex.md](hex.md) with the two opt-in steps: the surface map's distortion"
    echo "smoothed before the first volumetric map (\`--smooth-surface-map\`, \`smooth_surface_map()\`, with up"
    echo "to 3 more rounds of relaxation and smoothing while folds stay; by default it runs only as a"
    echo "second chance where tets stay flipped), and the joint untangling of what stays flipped over 3,"
    echo "6 and 12 vertex rings instead of 3, also on the unmerged polycube's map (\`--untangle-map\`,"
    echo "\`untangle_tet_map()\`). The times include both (docs/design/hex.md)."
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
