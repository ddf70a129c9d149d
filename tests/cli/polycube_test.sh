#!/usr/bin/env bash
# End-to-end checks of structmesh polycube. Usage: polycube_test.sh STRUCTMESH DATA_DIR WORK_DIR
source "$(dirname "$0")/common.sh" "$@"

# The torus: a polycube with one handle, written as OBJ quads, VTU with axis labels, a picture.
"$sm" polycube "$torus" -o "$work/p.obj" -o "$work/p.vtu" -o "$work/p.png" --deformed "$work/q.obj" \
  --json "$work/report.json" --quiet || fail "polycube torus.obj exited $?"
"$sm" check "$work/p.obj" --json "$work/check.json" --quiet >/dev/null
python3 - "$work" <<'END' || fail "polycube outputs"
import json, sys
work = sys.argv[1]
report = json.load(open(f"{work}/report.json"))
t = report["topology"]
assert t["input"]["handles"] == 1 and t["polycube"] == t["voxelized"], t
assert t["polycube"]["components"] == 1 and t["polycube"]["handles"] == 1 and t["polycube"]["voids"] == 0, t
assert report["energy_after"]["total"] <= report["energy_before"]["total"]
assert report["energy_after"]["corners"] >= 16  # a torus polycube has at least 16 corners
assert report["pseudo_polycube"]["deviation_degrees"] < report["pseudo_polycube"]["input_deviation_degrees"]
check = json.load(open(f"{work}/check.json"))
assert check["closed"] and check["edge_manifold"] and check["oriented"] and check["genus"] == 1, check
assert check["signed_volume"] > 0
quads = [l for l in open(f"{work}/p.obj") if l.startswith("f ")]
assert len(quads) == report["quads"] and all(len(l.split()) == 5 for l in quads)
END
grep -q 'Name="axis"' "$work/p.vtu" || fail "p.vtu has no axis cell data"
[[ -s "$work/p.png" && -s "$work/q.obj" ]] || fail "no picture or no deformed surface"

# Bad input: an open surface and an unsupported output exit 2.
expect_bad_input_rejected polycube obj

finish polycube
