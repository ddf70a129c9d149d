#!/usr/bin/env bash
# Builds every reader's libFuzzer target with clang (ASan + UBSan) and runs each for
# SECONDS (default 20) on its seed corpus. A crash or sanitizer report fails the run.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-20}
"$root/scripts/install-deps.sh"
build_dir=${BUILD_DIR:-$root/build-fuzz}
CC=clang CXX=clang++ cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSTRUCTMESH_FUZZ=ON
cmake --build "$build_dir" -j "$(nproc)"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0
for target in "$build_dir"/bin/fuzz_*; do
  name=$(basename "$target")
  format=${name#fuzz_}
  corpus="$work/$format"
  mkdir -p "$corpus"
  cp "$root/fuzz/corpus/$format/"* "$corpus/" 2>/dev/null || true
  echo "--- $name for ${seconds}s"
  # Crash artifacts land in the work folder; the log tail shows the finding.
  if ! (cd "$work" && "$target" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
        "$corpus" >"$work/$name.log" 2>&1); then
    echo "FAIL: $name found a problem:"
    tail -n 60 "$work/$name.log"
    status=1
  else
    grep -E "stat::number_of_executed_units|Done" "$work/$name.log" | tail -n 2
  fi
done
exit $status
