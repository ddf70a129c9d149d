#!/usr/bin/env bash
# Runs the partitioning benchmark (Tables 3.1/3.2 recomputed, CVT-GP vs exact, the
# 1M-segment runtime target) and stores the Markdown in bench/results/partition2d.md.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh" >/dev/null
data=${STRUCTMESH_DATA:-$root/../shared/data}
bench="${BUILD_DIR:-$root/build}/bin/bench_partition2d"
result="$root/bench/results/partition2d.md"
{
  echo "# Partitioning benchmark (issue 3, dissertation Tables 3.1/3.2)"
  echo
  echo "Measured $(date -u +%Y-%m-%d) on this machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo)," \
       "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'). One run each; times in seconds, wall clock."
  cat "$root/bench/partition2d/notes.md"
  echo
  echo "## Runtime and memory on a 1M-segment boundary (each in its own process)"
  for n in 250000 500000 1000000; do "$bench" large $n; done
  echo
  echo "## Tables 3.1/3.2 recomputed (default options: p = 8, imbalance 5%, cells = max(4000, 24k))"
  "$bench" tables "$data" "${SEGMENTS:-20000}"
  echo
  echo "## How far from optimal: CVT-GP vs --method exact"
  "$bench" exact
} | tee "$result.tmp"
mv "$result.tmp" "$result"
