#!/usr/bin/env bash
# End-to-end checks of structmesh hex. Usage: hex_test.sh STRUCTMESH DATA_DIR WORK_DIR
source "$(dirname "$0")/common.sh" "$@"

# The torus: a valid hex mesh in every format, its report, the polycube and the map.
"$sm" hex "$torus" --hexes 3000 -o "$work/h.vtu" -o "$work/h.mesh" -o "$work/h.msh" -o "$work/h.png" \
  --polycube "$work/p.obj" --parameterization "$work/map.vtu" --json "$work/report.json" --quiet ||
  fail "hex torus.obj exited $?"
"$sm" quality "$work/h.mesh" --json "$work/quality.json" --quiet >/dev/null || fail "quality h.mesh exited $?"
python3 - "$work" <<'END' || fail "hex outputs"
import json, sys
work = sys.argv[1]
r = json.load(open(f"{work}/report.json"))
assert r["inverted"] == 0 and r["invalid"] == 0 and r["scaled_jacobian"]["min"] > 0, r
assert 1500 <= r["hexes"] <= 6000, r["hexes"]
assert r["map"]["flipped"] == 0 and 0.9 < r["volume_distortion"] < 1.2, r["map"]
assert r["polycube"]["handles"] == 1 and r["geometric_deviation"] < 0.02, r
q = json.load(open(f"{work}/quality.json"))
# quality reads the .mesh back and finds the same mesh
text = json.dumps(q)
assert str(r["hexes"]) in text, text[:400]
END
grep -q 'Name="scaled_jacobian"' "$work/h.vtu" || fail "h.vtu has no scaled_jacobian cell data"
grep -q 'Name="u"' "$work/map.vtu" || fail "map.vtu has no u point data"
[[ -s "$work/h.png" && -s "$work/p.obj" && -s "$work/h.msh" ]] || fail "missing picture, polycube or .msh"

# Bad input: an open surface exits 2 and names it; an unsupported output exits 2; nothing written.
{ echo "OFF"; echo "4 2 0"; echo "0 0 0"; echo "1 0 0"; echo "0 1 0"; echo "0 0 1"; echo "3 0 2 1"; echo "3 0 1 3"; } \
  >"$work/open.off"
"$sm" hex "$work/open.off" -o "$work/open.vtu" 2>"$work/open.err"
status=$?
[[ $status -eq 2 ]] || fail "open surface: exit $status, expected 2"
grep -q "open.off" "$work/open.err" || fail "open surface: file not named in: $(cat "$work/open.err")"
[[ ! -e "$work/open.vtu" ]] || fail "open surface: an output was written"
"$sm" hex "$torus" -o "$work/h.stl" 2>/dev/null
status=$?
[[ $status -eq 2 ]] || fail "-o h.stl: exit $status, expected 2"
"$sm" hex "$torus" --hexes 100 --size 0.1 -o "$work/both.vtu" 2>/dev/null
status=$?
[[ $status -eq 2 ]] || fail "--hexes with --size: exit $status, expected 2"

finish hex
