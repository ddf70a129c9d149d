#!/usr/bin/env bash
# Runs the shape guarding benchmark (Table 2.1 recomputed on the data set's surfaces) and
# the star decomposition benchmark (§2.3), and stores the Markdown in bench/results/guard.md.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh" >/dev/null
data=${STRUCTMESH_DATA:-$root/../shared/data}
bin="${BUILD_DIR:-$root/build}/bin"
result="$root/bench/results/guard.md"
{
  echo "# Shape guarding benchmark (issue 5, dissertation §2.2)"
  echo
  echo "Measured $(date -u +%Y-%m-%d) on this machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo)," \
       "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'). One run each; times in seconds, wall clock."
  cat "$root/bench/guard/notes.md"
  echo
  echo "## Table 2.1 recomputed: greedy and exact (ILP) guards on every surface of the data set"
  echo
  "$bin/bench_guard" "$data"
  echo
  echo "## Table 2.2 recomputed: skeleton candidates against every tet vertex (exact ILP both)"
  echo
  echo "Each model simplified by edge collapse to about the dissertation's size (more vertices where the"
  echo "collapse folded the surface), tetrahedralized by TetGen, then guarded twice on the same surface."
  echo
  "$bin/bench_guard" "$data" --table-2.2
  echo
  echo "## Star decomposition (§2.3): the models tetrahedralized at their surface's mean edge length, ILP guards, relaxed and --strict"
  echo
  cat "$root/bench/star/notes.md"
  echo
  "$bin/bench_star" "$data" 1.0
} >"$result.tmp"
mv "$result.tmp" "$result"
echo "wrote $result"
