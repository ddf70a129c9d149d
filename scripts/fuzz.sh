#!/usr/bin/env bash
# Builds every reader's libFuzzer target with clang (ASan + UBSan) and runs each for
# SECONDS (default 20) on its seed corpus, as many at once as there are cores. A crash or
# sanitizer report fails the run.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-20}
"$root/scripts/install-deps.sh"
build_dir=${BUILD_DIR:-$root/build-fuzz}
CC=clang CXX=clang++ cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSTRUCTMESH_FUZZ=ON
cmake --build "$build_dir" -j "$(nproc)"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# One fuzzer per core at a time (each is single-threaded).
run_one() {
  local target=$1 name format corpus
  name=$(basename "$target")
  format=${name#fuzz_}
  corpus="$work/$format"
  mkdir -p "$corpus"
  cp "$root/fuzz/corpus/$format/"* "$corpus/" 2>/dev/null || true
  # Crash artifacts land in a folder per target; the log tail shows the finding.
  mkdir -p "$work/artifacts-$format"
  if (cd "$work/artifacts-$format" && "$target" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 \
      -print_final_stats=1 "$corpus" >"$work/$name.log" 2>&1); then
    echo ok >"$work/$name.status"
  else
    echo fail >"$work/$name.status"
  fi
}
for target in "$build_dir"/bin/fuzz_*; do
  while (($(jobs -rp | wc -l) >= $(nproc))); do wait -n || true; done
  echo "--- $(basename "$target") for ${seconds}s"
  run_one "$target" &
done
wait
status=0
for target in "$build_dir"/bin/fuzz_*; do
  name=$(basename "$target")
  if [[ "$(cat "$work/$name.status" 2>/dev/null)" != ok ]]; then
    echo "FAIL: $name found a problem:"
    tail -n 60 "$work/$name.log"
    status=1
  else
    echo "$name: $(grep -E "stat::number_of_executed_units" "$work/$name.log" | tail -n 1)"
  fi
done
exit $status
