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

# Bad input every 3D command must reject: an open surface exits 2, names the file and writes
# nothing; an output format it does not write exits 2.  Usage: expect_bad_input_rejected CMD EXT
expect_bad_input_rejected() {
  local cmd=$1 ext=$2 status
  { echo "OFF"; echo "4 2 0"; echo "0 0 0"; echo "1 0 0"; echo "0 1 0"; echo "0 0 1"; echo "3 0 2 1"; echo "3 0 1 3"; } \
    >"$work/open.off"
  "$sm" "$cmd" "$work/open.off" -o "$work/open.$ext" 2>"$work/open.err"
  status=$?
  [[ $status -eq 2 ]] || fail "$cmd open surface: exit $status, expected 2"
  grep -q "open.off" "$work/open.err" || fail "$cmd open surface: file not named in: $(cat "$work/open.err")"
  [[ ! -e "$work/open.$ext" ]] || fail "$cmd open surface: an output was written"
  "$sm" "$cmd" "$torus" -o "$work/out.stl" 2>/dev/null
  status=$?
  [[ $status -eq 2 ]] || fail "$cmd -o out.stl: exit $status, expected 2"
}
