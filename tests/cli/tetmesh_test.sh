#!/usr/bin/env bash
# End-to-end checks of structmesh tetmesh. Usage: tetmesh_test.sh STRUCTMESH WORK_DIR
set -u
sm=$1
work=$2
rm -rf "$work"
mkdir -p "$work"
failed=0
fail() {
  echo "FAIL: $*"
  failed=$((failed + 1))
}

# A unit cube as OFF, outward; the same with the faces flipped; and with one face missing.
cat >"$work/cube.off" <<'END'
OFF
8 12 0
0 0 0
1 0 0
0 1 0
1 1 0
0 0 1
1 0 1
0 1 1
1 1 1
3 0 2 3
3 0 3 1
3 4 5 7
3 4 7 6
3 0 1 5
3 0 5 4
3 2 6 7
3 2 7 3
3 0 4 6
3 0 6 2
3 1 3 7
3 1 7 5
END
awk 'NR > 10 && NF == 4 { print $1, $2, $4, $3; next } { print }' "$work/cube.off" >"$work/inward.off"
{ sed -n 1p "$work/cube.off"; echo "8 11 0"; sed -n '3,21p' "$work/cube.off"; } >"$work/open.off"

"$sm" tetmesh "$work/cube.off" -o "$work/cube.mesh" -o "$work/cube.vtu" -o "$work/cube.msh" --size 0.3 \
  --json "$work/cube.json" >"$work/out.txt" 2>&1 || fail "tetmesh cube.off exit $? $(cat "$work/out.txt")"
grep -q "tets" "$work/out.txt" || fail "no summary line"
for f in cube.mesh cube.vtu cube.msh; do
  "$sm" check "$work/$f" >"$work/check.txt" 2>&1 || fail "check $f: $(cat "$work/check.txt")"
done
/usr/bin/python3 - "$work/cube.json" <<'PY' || fail "cube report"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["tets"] > 0 and d["points"] >= 8, d
assert d["boundary_faces"] == 12, d
assert abs(d["mesh_volume"] - 1) < 1e-9 and abs(d["surface_volume"] - 1) < 1e-9, d
assert 0 < d["min_dihedral_deg"] < 90 and d["seconds"] >= 0, d
PY

"$sm" tetmesh "$work/cube.off" --quiet -o "$work/quiet.mesh" >"$work/quiet.txt" 2>&1 || fail "--quiet exit"
[[ ! -s "$work/quiet.txt" ]] || fail "--quiet printed: $(cat "$work/quiet.txt")"

# an open surface: exit 2, a message on stderr naming the file and the boundary edges, no output
"$sm" tetmesh "$work/open.off" -o "$work/open.mesh" >"$work/open.out" 2>"$work/open.err"
code=$?
[[ $code -eq 2 ]] || fail "open surface exit $code, wanted 2"
grep -q "open\.off.*boundary edges" "$work/open.err" || fail "open surface message: $(cat "$work/open.err")"
[[ ! -e "$work/open.mesh" ]] || fail "open surface wrote a mesh"

# inward normals: exit 2 pointing at --repair; with --repair it meshes
"$sm" tetmesh "$work/inward.off" -o "$work/inward.mesh" >/dev/null 2>"$work/inward.err"
code=$?
[[ $code -eq 2 ]] || fail "inward surface exit $code, wanted 2"
grep -q "inward.*--repair" "$work/inward.err" || fail "inward message: $(cat "$work/inward.err")"
"$sm" tetmesh "$work/inward.off" --repair -o "$work/repaired.mesh" >"$work/repair.txt" 2>&1 ||
  fail "--repair exit: $(cat "$work/repair.txt")"
grep -q "flipped" "$work/repair.txt" || fail "--repair says nothing"
"$sm" check "$work/repaired.mesh" >/dev/null 2>&1 || fail "repaired mesh invalid"

# bad usage
"$sm" tetmesh "$work/cube.off" -o "$work/cube.obj" >/dev/null 2>&1
[[ $? -eq 2 ]] || fail "tetmesh -o .obj should exit 2"
"$sm" tetmesh "$work/cube.off" --radius-edge 0.5 >/dev/null 2>&1
[[ $? -eq 2 ]] || fail "--radius-edge 0.5 should exit 2"

echo "tetmesh: $failed failed"
[[ $failed -eq 0 ]]
