#!/usr/bin/env bash
# Runs the polycube construction benchmark (chapter 4: Table 5.1's construction stages and
# Table 4.1's alpha trade-off) and stores the Markdown in bench/results/polycube.md.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh" >/dev/null
data=${STRUCTMESH_DATA:-$root/../shared/data}
bin="${BUILD_DIR:-$root/build}/bin"
result="$root/bench/results/polycube.md"
{
  echo "# Polycube construction benchmark (issue 6, dissertation ch. 4)"
  echo
  echo "Measured $(date -u +%Y-%m-%d) on this machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo)," \
       "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'). One run each; times in seconds, wall clock."
  cat "$root/bench/polycube/notes.md"
  echo
  "$bin/bench_polycube" "$data"
} >"$result.tmp"
mv "$result.tmp" "$result"
echo "wrote $result"
