# Shared preamble of the end-to-end CLI checks that read the shared data; sourced as
#   source common.sh "$@"   (arguments: STRUCTMESH DATA_DIR WORK_DIR)
# Sets sm, data, work (emptied), torus, counts failures with fail(), ends with finish NAME.
set -u
sm=$1
data=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
failed=0
fail() {
  echo "FAIL: $*"
  failed=$((failed + 1))
}
finish() {
  if ((failed > 0)); then
    echo "$failed check(s) failed"
    exit 1
  fi
  echo "$1 CLI checks passed"
}
torus="$data/surfaces/torus.obj"
if [[ ! -f "$torus" ]]; then
  echo "no $torus: STRUCTMESH_DATA must point at the shared data"
  exit 1
fi
