#!/usr/bin/env bash
# End-to-end checks of the CLI. Usage: cli_test.sh STRUCTMESH DATA_DIR WORK_DIR
# Each check runs a command and asserts its exit code and (optionally) output text.
set -u
sm=$1
data=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
passed=0
failed=0

# expect CODE PATTERN -- COMMAND...: exit code must be CODE; PATTERN (grep -E, may be
# empty) must match the combined stdout+stderr.
expect() {
  local want=$1 pattern=$2
  shift 3
  local output code
  output=$("$@" 2>&1)
  code=$?
  if [[ $code -ne $want ]]; then
    echo "FAIL (exit $code, wanted $want): $*"
    echo "$output" | tail -n 20
    failed=$((failed + 1))
  elif [[ -n $pattern ]] && ! grep -qE -- "$pattern" <<<"$output"; then
    echo "FAIL (output lacks /$pattern/): $*"
    echo "$output" | tail -n 20
    failed=$((failed + 1))
  else
    passed=$((passed + 1))
  fi
}

# jq-free JSON field check with python (the system one has json).
json_field() { /usr/bin/python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d$2)" "$1"; }

# usage and help
expect 0 "check" -- "$sm" --help
expect 0 "--json" -- "$sm" check --help
expect 2 "" -- "$sm"
expect 2 "" -- "$sm" check
expect 2 "" -- "$sm" frobnicate
expect 2 "" -- "$sm" generate teapot -o "$work/x.geojson"

# bad input: a clear one-line message naming the file, exit 2, never a crash
expect 2 "missing\.obj.*cannot open" -- "$sm" check "$work/missing.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n' >"$work/bad_index.obj"
expect 2 "bad_index\.obj:4:" -- "$sm" check "$work/bad_index.obj"
printf 'OFF\n3 1 0\n0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n' >"$work/nan.off"
expect 2 "nan\.off:4:" -- "$sm" check "$work/nan.off"
: >"$work/empty.stl"
expect 2 "empty\.stl" -- "$sm" check "$work/empty.stl"
printf 'solid x\n' >"$work/truncated.stl"
expect 2 "truncated\.stl" -- "$sm" check "$work/truncated.stl"
printf '{"type": "Polygon", "coordinates": [[[0,0],[1,0]' >"$work/broken.geojson"
expect 2 "broken\.geojson" -- "$sm" check "$work/broken.geojson"
expect 2 "unknown file extension" -- "$sm" check "$work/file.xyz"

# an open surface is invalid as a solid; a closed tetrahedron is valid
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n' >"$work/tet.obj"
expect 0 "genus +0" -- "$sm" check "$work/tet.obj" --json "$work/tet.json"
[[ $(json_field "$work/tet.json" "['genus']") == 0 ]] && passed=$((passed + 1)) || { echo "FAIL: tet genus"; failed=$((failed + 1)); }
head -n 7 "$work/tet.obj" >"$work/open.obj"
expect 2 "open-edge|boundary" -- "$sm" check "$work/open.obj"

# generated regions are valid, written in every region format, and re-read
expect 0 "wrote" -- "$sm" generate key --segments 500 -o "$work/key.geojson" -o "$work/key.poly" -o "$work/key.svg"
expect 0 "holes.* 1" -- "$sm" check "$work/key.geojson"
expect 0 "" -- "$sm" check "$work/key.poly"
expect 0 "wrote" -- "$sm" generate pipe --segments 900 -o "$work/pipe.geojson" --json "$work/pipe.json"
[[ $(json_field "$work/pipe.json" "['holes']") == 9 ]] && passed=$((passed + 1)) || { echo "FAIL: pipe holes"; failed=$((failed + 1)); }
grep -q "<svg" "$work/key.svg" && passed=$((passed + 1)) || { echo "FAIL: key.svg"; failed=$((failed + 1)); }
# a built-in solid is written in a surface format and checks as a solid boundary of its genus;
# a picture format is refused for it
expect 0 "wrote" -- "$sm" generate washer -o "$work/washer.off" --json "$work/washer.json"
expect 0 "genus +1" -- "$sm" check "$work/washer.off"
expect 2 "PNG" -- "$sm" generate washer -o "$work/washer.png"
expect 2 "segments" -- "$sm" generate washer --segments 100 -o "$work/washer2.off"

# quality: unit cube hex mesh via MEDIT -> perfect, and its JSON
cat >"$work/cube.mesh" <<'MESH'
MeshVersionFormatted 2
Dimension 3
Vertices
8
0 0 0 0
1 0 0 0
1 1 0 0
0 1 0 0
0 0 1 0
1 0 1 0
1 1 1 0
0 1 1 0
Hexahedra
1
1 2 3 4 5 6 7 8 0
End
MESH
expect 0 "hexahedra" -- "$sm" quality "$work/cube.mesh" --json "$work/cube.json" -o "$work/cube.vtu"
[[ $(json_field "$work/cube.json" "['scaled_jacobian']['min']") == 1.0 ]] && passed=$((passed + 1)) || { echo "FAIL: cube SJ"; failed=$((failed + 1)); }
expect 0 "" -- "$sm" convert "$work/cube.mesh" -o "$work/cube.msh"
expect 0 "" -- "$sm" check "$work/cube.msh"
expect 2 "holds only triangles" -- "$sm" quality "$work/tet.obj"
# nothing half-written: a failed write leaves no output behind
expect 1 "" -- "$sm" convert "$work/cube.mesh" -o "$work/no-such-dir/cube.vtu"
[[ ! -e "$work/no-such-dir" ]] && passed=$((passed + 1)) || { echo "FAIL: partial output"; failed=$((failed + 1)); }

# a planar quad mesh is checked as a 2D mesh: a flipped quad is inverted, and the line is named
cat >"$work/quads.mesh" <<'MESH'
MeshVersionFormatted 2
Dimension 2
Vertices
6
0 0 0
1 0 0
2 0 0
0 1 0
1 1 0
2 1 0
Quadrilaterals
2
1 2 5 4 0
2 3 6 5 0
End
MESH
expect 0 "planar mesh" -- "$sm" check "$work/quads.mesh"
sed 's/^2 3 6 5 0$/5 6 3 2 0/' "$work/quads.mesh" >"$work/flipped.mesh"
expect 2 "flipped\.mesh:14: inverted-element" -- "$sm" check "$work/flipped.mesh"

# partition2d: the parts file reads back as a valid partition (parts share edges), the report has the metrics
expect 0 "R_W" -- "$sm" partition2d key --segments 2000 --parts 8 --cells 600 -o "$work/parts.geojson" \
  -o "$work/parts.svg" -o "$work/parts.png" --json "$work/parts.json"
expect 0 "polygons / rings / holes +8 /" -- "$sm" check "$work/parts.geojson" --as partition
expect 2 "touches polygon" -- "$sm" check "$work/parts.geojson"  # as one region, parts sharing edges are invalid
[[ $(json_field "$work/parts.json" "['parts']") == 8 ]] || { echo "FAIL: partition2d report parts"; failed=$((failed + 1)); }
[[ $(json_field "$work/parts.json" "['max_components_per_part']") == 1 ]] || { echo "FAIL: partition2d components"; failed=$((failed + 1)); }
head -c 8 "$work/parts.png" | od -An -c | grep -q "P   N   G" || { echo "FAIL: parts.png is not a PNG"; failed=$((failed + 1)); }
expect 0 "metis" -- "$sm" partition2d "$work/key.geojson" --parts 4 --method metis --cells 2000
expect 2 "even" -- "$sm" partition2d key --parts 4 --p 7
expect 2 "" -- "$sm" partition2d key --parts 0
expect 2 "" -- "$sm" partition2d key --parts 4 --method simplex
expect 2 "exact solves graphs of at most" -- "$sm" partition2d key --parts 2 --method exact --cells 5000
expect 2 "partition2d writes" -- "$sm" partition2d key --parts 2 -o "$work/parts.obj"
printf '{"type": "Polygon", "coordinates": [[[0,0],[2,2],[2,0],[0,2],[0,0]]]}' >"$work/bowtie.geojson"
expect 2 "not valid" -- "$sm" partition2d "$work/bowtie.geojson" --parts 2

# quad2d: all-quad, conforming, valid; every writer; identical meshes for 1 and 2
# threads and for 1, 2 and 4 MPI ranks (the merged file of an MPI run is the same bytes)
printf '{"type":"Polygon","coordinates":[[[0,0],[400,0],[400,200],[0,200],[0,0]],[[250,60],[290,60],[290,120],[250,120],[250,60]]]}' >"$work/plate.geojson"
expect 0 "inverted 0," -- "$sm" quad2d "$work/plate.geojson" --size 6 --parts 4 --threads 1 -o "$work/plate.vtu" \
  -o "$work/plate.msh" -o "$work/plate.mesh" -o "$work/plate.pvtu" -o "$work/plate.png" --json "$work/plate.json"
expect 0 "" -- "$sm" check "$work/plate.vtu"
expect 0 "" -- "$sm" check "$work/plate.msh"
expect 0 "scaled Jacobian" -- "$sm" quality "$work/plate.mesh"
[[ $(json_field "$work/plate.json" "['inverted']") == 0 ]] || { echo "FAIL: quad2d inverted"; failed=$((failed + 1)); }
/usr/bin/python3 -c "import json,sys; d=json.load(open(sys.argv[1])); sys.exit(0 if d['quads'] > 1000 and abs(d['mesh_area'] - d['region_area']) < 1e-9 * d['region_area'] else 1)" "$work/plate.json" ||
  { echo "FAIL: quad2d area or quad count"; failed=$((failed + 1)); }
head -c 8 "$work/plate.png" | od -An -c | grep -q "P   N   G" || { echo "FAIL: plate.png is not a PNG"; failed=$((failed + 1)); }
[[ -f "$work/plate_0.vtu" ]] || { echo "FAIL: plate.pvtu has no piece"; failed=$((failed + 1)); }
expect 0 "" -- "$sm" quad2d "$work/plate.geojson" --size 6 --parts 4 --threads 2 -o "$work/plate2.vtu"
cmp -s "$work/plate.vtu" "$work/plate2.vtu" || { echo "FAIL: quad2d differs between 1 and 2 threads"; failed=$((failed + 1)); }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# Under the sanitizers, OpenMPI's own start-up allocations would count as leaks.
mpi_asan=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0
for np in 1 2 4; do
  expect 0 "on $np ranks" -- env ASAN_OPTIONS="$mpi_asan" mpirun --oversubscribe -np $np "$sm" quad2d "$work/plate.geojson" --size 6 --parts 4 \
    --threads 1 -o "$work/mpi$np.pvtu" --merged "$work/mpi$np.vtu" --json "$work/mpi$np.json"
  cmp -s "$work/plate.vtu" "$work/mpi$np.vtu" || { echo "FAIL: quad2d on $np MPI ranks differs from threads"; failed=$((failed + 1)); }
  [[ -f "$work/mpi${np}_$((np - 1)).vtu" ]] || { echo "FAIL: no piece of rank $((np - 1))"; failed=$((failed + 1)); }
done
expect 2 "" -- "$sm" quad2d "$work/plate.geojson" --size -1
expect 2 "" -- "$sm" quad2d "$work/plate.geojson" --size 5 --quads 100
expect 2 "quad2d writes" -- "$sm" quad2d "$work/plate.geojson" --size 6 -o "$work/plate.obj"
expect 2 "lon/lat" -- "$sm" quad2d "$work/plate.geojson" --size 6 --lonlat-output
expect 2 "view" -- "$sm" quad2d "$work/plate.geojson" --size 6 --view 1,2,3 -o "$work/v.png"
expect 2 "not valid" -- "$sm" quad2d "$work/bowtie.geojson" --size 0.1

# real data: valid, open and self-intersecting models are told apart
if [[ -d "$data/surfaces" ]]; then
  expect 0 "genus +1" -- "$sm" check "$data/surfaces/rocker-arm.obj"
  expect 2 "self-intersections +32" -- "$sm" check "$data/surfaces/tosca_centaur.off"
  expect 2 "closed +no" -- "$sm" check "$data/surfaces/tosca_dog0.off"
  expect 0 "" -- "$sm" check "$data/regions/west_bay_galveston.geojson"
else
  echo "FAIL: test data folder $data is missing (set STRUCTMESH_DATA)"
  failed=$((failed + 1))
fi

echo "$passed passed, $failed failed"
[[ $failed -eq 0 ]]
