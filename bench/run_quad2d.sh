#!/usr/bin/env bash
# Runs the parallel quad meshing benchmark (Table 3.4 recomputed, Gmsh 4.8 side by
# side, thread and MPI scaling, the large-mesh run) and stores the Markdown in
# bench/results/quad2d.md.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh" >/dev/null
data=${STRUCTMESH_DATA:-$root/../shared/data}
bin="${BUILD_DIR:-$root/build}/bin"
result="$root/bench/results/quad2d.md"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
{
  echo "# Parallel quad meshing benchmark (issue 4, dissertation §3.3–3.4)"
  echo
  echo "Measured $(date -u +%Y-%m-%d) on this machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo)," \
       "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'). One run each (the thread scaling: three, alternating); times in seconds, wall clock."
  cat "$root/bench/quad2d/notes.md"
  echo
  echo "## Beside Gmsh 4.8.4 (same region, same size, quality measured the same way)"
  echo
  "$bin/bench_quad2d" gmsh
  echo
  echo "## Table 3.4 recomputed: every partitioning, the same meshers"
  echo
  "$bin/bench_quad2d" table "$data" "${SEGMENTS:-2000}"
  echo
  echo "## Scaling on one machine"
  echo
  "$bin/bench_quad2d" scaling "${SCALING_QUADS:-2000000}"
  echo
  echo "### MPI ranks (Key, 20,000 segments, about 2M quads, 64 parts, one thread per rank)"
  echo
  echo "| ranks | quads | total s | paving s (slowest rank) | quads/s |"
  echo "|---:|---:|---:|---:|---:|"
  for np in 1 2; do
    mpirun --oversubscribe -np $np "$bin/structmesh" quad2d key --segments 20000 --quads 2000000 --parts 64 \
      --threads 1 -q --json "$work/mpi$np.json" </dev/null
    /usr/bin/python3 -c "import json,sys; d=json.load(open(sys.argv[1])); t=d['stage_seconds']['total']; print(f\"| {d['ranks']} | {d['quads']} | {t:.2f} | {max(d['rank_paving_seconds']):.2f} | {d['quads']/t:.0f} |\")" "$work/mpi$np.json"
  done
  echo
  echo "## Large run (Gulf of Mexico, about ${LARGE_QUADS:-20000000} quads, default parts, all cores)"
  echo
  "$bin/bench_quad2d" large "$data" "${LARGE_QUADS:-20000000}"
} | tee "$result.tmp"
mv "$result.tmp" "$result"
