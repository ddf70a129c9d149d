#!/usr/bin/env bash
# End-to-end checks of structmesh guard. Usage: guard_test.sh STRUCTMESH DATA_DIR WORK_DIR
source "$(dirname "$0")/common.sh" "$@"

# A torus surface, and the same torus as a tet mesh (its boundary is the surface).
"$sm" guard "$torus" -o "$work/guards.json" -o "$work/faces.vtu" --json "$work/report.json" --quiet ||
  fail "guard torus.obj exited $?"
"$sm" tetmesh "$torus" -o "$work/torus.mesh" --quiet || fail "tetmesh torus.obj exited $?"
"$sm" guard "$work/torus.mesh" --method greedy -o "$work/solid.json" --quiet || fail "guard torus.mesh exited $?"
python3 - "$work" <<'END' || fail "guard outputs"
import json, sys
work = sys.argv[1]
guards = json.load(open(f"{work}/guards.json"))
report = json.load(open(f"{work}/report.json"))
faces = report["faces"]
assigned = sorted(f for g in guards["guards"] for f in g["faces"])
assert assigned == list(range(faces)), "every face belongs to exactly one guard"
# A point inside a torus sees only an arc of the tube: several guards, ILP <= greedy.
assert 3 <= len(guards["guards"]) <= report["greedy_guards"], (len(guards["guards"]), report["greedy_guards"])
assert report["uncovered_faces"] == 0 and report["optimal"]
for g in guards["guards"]:
    assert len(g["position"]) == 3
for a, b in guards["graph"]:
    assert 0 <= a < b < len(guards["guards"])
solid = json.load(open(f"{work}/solid.json"))
assert sorted(f for g in solid["guards"] for f in g["faces"]) == list(range(faces)), "solid input: same faces"
END
grep -q 'Name="guard"' "$work/faces.vtu" || fail "faces.vtu has no guard cell data"

# --candidates: a rerun on the candidates of guards.json gives the same guards, by every method.
for method in ilp pilp; do
  "$sm" guard "$torus" --method $method -o "$work/first_$method.json" --quiet || fail "guard --method $method exited $?"
  "$sm" guard "$torus" --method $method --candidates "$work/first_$method.json" -o "$work/again_$method.json" --quiet ||
    fail "guard --candidates ($method) exited $?"
  python3 - "$work/first_$method.json" "$work/again_$method.json" <<'END' || fail "--candidates rerun ($method) differs"
import json, sys
first, again = (json.load(open(p)) for p in sys.argv[1:3])
assert len(first["candidates"]) > 0 and first["candidates"] == again["candidates"]
assert first["guards"] == again["guards"], (len(first["guards"]), len(again["guards"]))
END
done
echo '{"candidates": [[0, 0]]}' >"$work/short.json"
"$sm" guard "$torus" --candidates "$work/short.json" -o "$work/short_out.json" 2>"$work/short.err"
status=$?
[[ $status -eq 2 ]] || fail "malformed candidates: exit $status, expected 2"
grep -q 'short.json: candidates\[0\]' "$work/short.err" || fail "malformed candidates: not named in: $(cat "$work/short.err")"

# Bad input: an open surface, a missing file.
{ echo "OFF"; echo "4 2 0"; echo "0 0 0"; echo "1 0 0"; echo "0 1 0"; echo "0 0 1"; echo "3 0 2 1"; echo "3 0 1 3"; } \
  >"$work/open.off"
"$sm" guard "$work/open.off" -o "$work/open.json" 2>"$work/open.err"
status=$?
[[ $status -eq 2 ]] || fail "open surface: exit $status, expected 2"
grep -q "open" "$work/open.err" || fail "open surface: no 'open' in: $(cat "$work/open.err")"
[[ ! -e "$work/open.json" ]] || fail "open surface: an output was written"
# --repair closes the hole (two triangles) and guards the closed surface.
"$sm" guard "$work/open.off" --repair -o "$work/repaired.json" --json "$work/repaired_report.json" --quiet ||
  fail "guard --repair on an open surface exited $?"
python3 - "$work" <<'END' || fail "guard --repair outputs"
import json, sys
work = sys.argv[1]
report = json.load(open(f"{work}/repaired_report.json"))
assert report["repaired"]["holes_filled"] == 1 and report["repaired"]["faces_added"] == 2, report["repaired"]
assert report["faces"] == 4 and report["guards"] == 1 and report["uncovered_faces"] == 0
guards = json.load(open(f"{work}/repaired.json"))["guards"]
assert sorted(f for g in guards for f in g["faces"]) == [0, 1, 2, 3]
END
"$sm" guard "$work/missing.obj" -o "$work/missing.json" 2>/dev/null
status=$?
[[ $status -eq 2 ]] || fail "missing file: exit $status, expected 2"

finish guard
