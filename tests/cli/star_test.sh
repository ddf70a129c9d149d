#!/usr/bin/env bash
# End-to-end checks of structmesh star. Usage: star_test.sh STRUCTMESH DATA_DIR WORK_DIR
source "$(dirname "$0")/common.sh" "$@"

# Guards from `guard`, then a strict and a relaxed decomposition of the same solid.
"$sm" tetmesh "$torus" -o "$work/torus.mesh" --quiet || fail "tetmesh exited $?"
"$sm" guard "$work/torus.mesh" -o "$work/guards.json" --quiet || fail "guard exited $?"
"$sm" star "$work/torus.mesh" --guards "$work/guards.json" --strict -o "$work/strict.vtu" -o "$work/strict.mesh" \
  --json "$work/strict.json" --quiet || fail "star --strict exited $?"
"$sm" star "$work/torus.mesh" --guards "$work/guards.json" -o "$work/relaxed.vtu" --json "$work/relaxed.json" \
  --quiet || fail "star exited $?"
# A surface as input: tetrahedralized and guarded inside the command.
"$sm" star "$torus" --method greedy -o "$work/surface.mesh" --json "$work/surface.json" --quiet ||
  fail "star on a surface exited $?"
python3 - "$work" <<'END' || fail "star outputs"
import json, sys
work = sys.argv[1]
guards = json.load(open(f"{work}/guards.json"))["guards"]
strict = json.load(open(f"{work}/strict.json"))
relaxed = json.load(open(f"{work}/relaxed.json"))
for report in (strict, relaxed):
    assert sum(p["tets"] for p in report["parts"]) == report["tets"], "every tet in exactly one part"
    assert report["guards"] == len(guards)
    assert report["part_count"] >= len(guards) - report["dropped_guards"]
assert strict["star_shaped_parts"] == strict["part_count"], "--strict: every part star-shaped"
assert strict["visible_fraction"] == 1.0
assert all(p["kernel_violations"] == 0 for p in strict["parts"])
assert relaxed["part_count"] <= strict["part_count"]
assert 0.99 <= relaxed["visible_fraction"] <= 1.0, relaxed["visible_fraction"]
# The MEDIT file carries the part id as each tet's reference.
lines = open(f"{work}/strict.mesh").read().split("\n")
k = lines.index("Tetrahedra")
count = int(lines[k + 1])
refs = [int(l.split()[4]) for l in lines[k + 2:k + 2 + count]]
assert count == strict["tets"] and set(refs) == set(range(strict["part_count"])), "part ids as references"
surface = json.load(open(f"{work}/surface.json"))
assert surface["tets"] > 0 and surface["part_count"] >= 2
END
grep -q 'Name="part"' "$work/strict.vtu" || fail "strict.vtu has no part cell data"

# Bad input: a guards file that is not JSON, one without positions, a surface file as -o.
echo "not json" >"$work/bad.json"
"$sm" star "$work/torus.mesh" --guards "$work/bad.json" -o "$work/bad.vtu" 2>"$work/bad.err"
status=$?
[[ $status -eq 2 ]] || fail "bad guards file: exit $status, expected 2"
grep -q "bad.json" "$work/bad.err" || fail "bad guards file: not named in: $(cat "$work/bad.err")"
[[ ! -e "$work/bad.vtu" ]] || fail "bad guards file: an output was written"
echo '{"guards": [{"faces": []}]}' >"$work/nopos.json"
"$sm" star "$work/torus.mesh" --guards "$work/nopos.json" -o "$work/nopos.vtu" 2>/dev/null
status=$?
[[ $status -eq 2 ]] || fail "guard without position: exit $status, expected 2"
"$sm" star "$work/torus.mesh" -o "$work/parts.obj" 2>/dev/null
status=$?
[[ $status -eq 2 ]] || fail "-o parts.obj: exit $status, expected 2"

finish star
