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
# D_v >= 1 (equality for a volume-preserving map); defined only without flipped tets
assert r["map"]["flipped"] == 0 and 1.0 <= r["volume_distortion"] < 3, (r["map"], r["volume_distortion"])
assert r["polycube"]["handles"] == 1 and r["geometric_deviation"] < 0.02, r
# the map's stage times are reported and add up to no more than the map's stage
m = r["map"]
assert all(m[k] >= 0 for k in ("seconds_frames", "seconds_solve", "seconds_untangle")), m
assert m["seconds_frames"] + m["seconds_solve"] + m["seconds_untangle"] <= r["stage_seconds"]["volumetric map"] + 1e-3, m
# the map's boundary leaves P only where the untangling released points; far off, the mesh is made from P
assert m["released_boundary_points"] > 0 or m["map_boundary_drift_voxels"] == 0, m
assert not m["map_boundary_skipped"] or (m["map_boundary_drift_voxels"] > 50 and m["boundary_from_p_kept"]), m
# the worst hex meets the issue's 0.3 target; the mean is 0.93 at this coarse size (0.948 at 11k)
assert r["scaled_jacobian"]["min"] >= 0.3 and r["scaled_jacobian"]["mean"] >= 0.9, r["scaled_jacobian"]
# the polycube's facet planes (merged by default) are reported, at least 2 per axis
assert all(n >= 2 for n in r["polycube"]["facet_planes"]), r["polycube"]
q = json.load(open(f"{work}/quality.json"))
# quality reads the .mesh back and finds the same mesh
text = json.dumps(q)
assert str(r["hexes"]) in text, text[:400]
END
grep -q 'Name="scaled_jacobian"' "$work/h.vtu" || fail "h.vtu has no scaled_jacobian cell data"
grep -q 'Name="u"' "$work/map.vtu" || fail "map.vtu has no u point data"
[[ -s "$work/h.png" && -s "$work/p.obj" && -s "$work/h.msh" ]] || fail "missing picture, polycube or .msh"

# --polish-below above the worst hex: fresh starts of the worst cluster are tried and joint
# ascents run, and the worst hex does not drop.
"$sm" hex "$torus" --hexes 3000 --polish-below 0.95 -o "$work/polished.vtu" --json "$work/polished.json" --quiet ||
  fail "hex --polish-below 0.95 exited $?"
python3 - "$work" <<'END' || fail "--polish-below"
import json, sys
work = sys.argv[1]
plain, polished = (json.load(open(f"{work}/{name}.json")) for name in ("report", "polished"))
assert polished["smoothing"]["polish_rounds"] >= 1, polished["smoothing"]
assert plain["smoothing"]["polish_rounds"] == 0, plain["smoothing"]
assert polished["smoothing"]["restarts_tried"] >= 1, polished["smoothing"]
assert plain["smoothing"]["restarts_tried"] == 0, plain["smoothing"]
assert polished["smoothing"]["restarts"] <= polished["smoothing"]["restarts_tried"], polished["smoothing"]
assert polished["inverted"] == 0 and polished["scaled_jacobian"]["min"] >= plain["scaled_jacobian"]["min"], (
    plain["scaled_jacobian"], polished["scaled_jacobian"])
END
"$sm" hex "$torus" --hexes 100 --polish-below 2 -o "$work/bad.vtu" 2>/dev/null
status=$?
[[ $status -eq 2 ]] || fail "--polish-below 2: exit $status, expected 2"
"$sm" hex "$torus" --hexes 100 --restarts -1 -o "$work/bad.vtu" 2>/dev/null
status=$?
[[ $status -eq 2 ]] || fail "--restarts -1: exit $status, expected 2"

# --mean-below: 0 runs no ascent of the mean, 1 always does; it raises the mean and holds
# the worst hex.
for below in 0 1; do
  "$sm" hex "$torus" --hexes 3000 --mean-below $below -o "$work/mean$below.vtu" --json "$work/mean$below.json" --quiet ||
    fail "hex --mean-below $below exited $?"
done
python3 - "$work" <<'END' || fail "--mean-below"
import json, sys
work = sys.argv[1]
none, always = (json.load(open(f"{work}/mean{below}.json")) for below in (0, 1))
assert none["smoothing"]["mean_ascent_rounds"] == 0, none["smoothing"]
assert always["smoothing"]["mean_ascent_rounds"] >= 1, always["smoothing"]
assert always["inverted"] == 0
assert always["scaled_jacobian"]["mean"] > none["scaled_jacobian"]["mean"], (none["scaled_jacobian"], always["scaled_jacobian"])
assert always["scaled_jacobian"]["min"] >= none["scaled_jacobian"]["min"], (none["scaled_jacobian"], always["scaled_jacobian"])
END
"$sm" hex "$torus" --hexes 100 --mean-below -0.5 -o "$work/bad.vtu" 2>/dev/null
status=$?
[[ $status -eq 2 ]] || fail "--mean-below -0.5: exit $status, expected 2"

# Bad input: an open surface and an unsupported output exit 2.
expect_bad_input_rejected hex vtu
# --repair: the torus with one face removed and every face turned inward is refused without
# it (exit 2) and meshed with it, its hole closed and its surface turned outward.
python3 - "$torus" "$work/holed.obj" <<'END' || fail "making holed.obj"
import sys
lines = open(sys.argv[1]).read().splitlines()
faces = [i for i, l in enumerate(lines) if l.startswith("f ")]
del lines[faces[0]]
out = []
for l in lines:
    if l.startswith("f "):
        parts = l.split()
        l = " ".join([parts[0]] + parts[1:][::-1])
    out.append(l)
open(sys.argv[2], "w").write("\n".join(out) + "\n")
END
"$sm" hex "$work/holed.obj" --hexes 1000 -o "$work/holed.vtu" 2>/dev/null
status=$?
[[ $status -eq 2 ]] || fail "hex of a holed, inward surface: exit $status, expected 2"
"$sm" hex "$work/holed.obj" --hexes 1000 --repair -o "$work/holed.vtu" --json "$work/holed.json" --quiet ||
  fail "hex --repair exited $?"
python3 - "$work" <<'END' || fail "hex --repair report"
import json, sys
r = json.load(open(f"{sys.argv[1]}/holed.json"))
assert r["repaired"] == {"holes_filled": 1, "faces_added": 1, "flipped": True}, r["repaired"]
assert r["inverted"] == 0 and r["scaled_jacobian"]["min"] > 0, r["scaled_jacobian"]
END
"$sm" hex "$torus" --hexes 100 --size 0.1 -o "$work/both.vtu" 2>/dev/null
status=$?
[[ $status -eq 2 ]] || fail "--hexes with --size: exit $status, expected 2"
# --max-deviation below the torus's D_g (the same run as the first above): exit 1 with a
# message, no mesh and no polycube written, the report written and saying why. The first
# run, under no limit and far below the warning level, has no warnings.
limit=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['geometric_deviation'] / 2)" "$work/report.json")
"$sm" hex "$torus" --hexes 3000 --max-deviation "$limit" -o "$work/far.vtu" --polycube "$work/far.obj" \
  --json "$work/far.json" --quiet 2>"$work/far.err"
status=$?
[[ $status -eq 1 ]] || fail "--max-deviation $limit: exit $status, expected 1"
grep -q "more than --max-deviation" "$work/far.err" || fail "--max-deviation message: $(cat "$work/far.err")"
[[ ! -e "$work/far.vtu" && ! -e "$work/far.obj" ]] || fail "--max-deviation left a mesh behind"
python3 - "$work" <<'END' || fail "--max-deviation report"
import json, sys
work = sys.argv[1]
plain, far = (json.load(open(f"{work}/{name}.json")) for name in ("report", "far"))
assert plain["warnings"] == [] and plain["max_deviation_exceeded"] is False, plain["warnings"]
assert far["max_deviation_exceeded"] is True and far["geometric_deviation"] == plain["geometric_deviation"], far
END
"$sm" hex "$torus" --hexes 100 --max-deviation 1.5 -o "$work/bad.vtu" 2>/dev/null
status=$?
[[ $status -eq 2 ]] || fail "--max-deviation 1.5: exit $status, expected 2"
# A grid above --max-hexes is refused (exit 1, runtime) with a message, and nothing written.
"$sm" hex "$torus" --hexes 3000 --max-hexes 500 -o "$work/big.vtu" 2>"$work/big.err"
status=$?
[[ $status -eq 1 ]] || fail "--max-hexes 500: exit $status, expected 1"
grep -q "more than the limit of 500" "$work/big.err" || fail "--max-hexes message: $(cat "$work/big.err")"
[[ ! -e "$work/big.vtu" ]] || fail "--max-hexes left big.vtu behind"

finish hex
