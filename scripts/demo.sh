#!/usr/bin/env bash
# Installs what is missing, builds, and runs the pipelines that exist so far on
# built-in inputs. Results and pictures go to out/.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
sm="${BUILD_DIR:-$root/build}/bin/structmesh"
out="$root/out"
mkdir -p "$out"

echo "== built-in regions of §3.4: the Key (1 hole) and the Pipe (9 holes)"
"$sm" generate key --segments 4000 -o "$out/key.geojson" -o "$out/key.poly" -o "$out/key.svg" -o "$out/key.png" --json "$out/key-generate.json"
"$sm" generate pipe --segments 8000 -o "$out/pipe.geojson" -o "$out/pipe.poly" -o "$out/pipe.svg" -o "$out/pipe.png" --json "$out/pipe-generate.json"

echo "== validate them as regions"
"$sm" check "$out/key.geojson" --json "$out/key-check.json"
"$sm" check "$out/pipe.poly" --json "$out/pipe-check.json"

echo "== geometry-aware partitioning (§3.2): Key into 32 parts, Pipe into 16, CVT-GP beside METIS"
"$sm" partition2d "$out/key.geojson" --parts 32 -o "$out/key-parts.geojson" -o "$out/key-parts.svg" -o "$out/key-parts.png" --json "$out/key-parts.json"
"$sm" partition2d "$out/key.geojson" --parts 32 --method metis -o "$out/key-parts-metis.png" --json "$out/key-parts-metis.json"
"$sm" partition2d "$out/pipe.geojson" --parts 16 -o "$out/pipe-parts.geojson" -o "$out/pipe-parts.png" --json "$out/pipe-parts.json"

echo "== parallel all-quad meshing (§3.3): Key in 32 parts, Pipe in 16; pictures coloured by scaled Jacobian"
"$sm" quad2d "$out/key.geojson" --parts 32 -o "$out/key-quads.vtu" -o "$out/key-quads.msh" -o "$out/key-quads.png" --json "$out/key-quads.json"
"$sm" quad2d "$out/pipe.geojson" --parts 16 -o "$out/pipe-quads.vtu" -o "$out/pipe-quads.png" --json "$out/pipe-quads.json"
echo "== the same Key mesh on 2 MPI ranks: one .pvtu piece per rank, and the merged file (identical to the threaded one)"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mpirun --oversubscribe -np 2 "$sm" quad2d "$out/key.geojson" --parts 32 --threads 1 -o "$out/key-quads-mpi.pvtu" \
  --merged "$out/key-quads-mpi.vtu" --json "$out/key-quads-mpi.json"
cmp "$out/key-quads.vtu" "$out/key-quads-mpi.vtu" && echo "MPI and threaded meshes are byte-identical"

echo "== 3D on a built-in solid (no data set needed): a tube around a trefoil knot, all-hex by polycube mapping"
"$sm" generate trefoil -o "$out/trefoil.obj" --json "$out/trefoil-generate.json"
"$sm" check "$out/trefoil.obj" --json "$out/trefoil-check.json"
"$sm" hex "$out/trefoil.obj" --hexes 10000 -o "$out/trefoil-hex.vtu" -o "$out/trefoil-hex.png" \
  --polycube "$out/trefoil-polycube.obj" --json "$out/trefoil-hex.json"

data=${STRUCTMESH_DATA:-$root/../shared/data}
if [[ -d "$data" ]]; then
  echo "== the Gulf of Mexico (lon/lat, 1,624 islands) into 128 parts"
  "$sm" partition2d "$data/regions/gulf_of_mexico.geojson" --parts 128 -o "$out/gulf-parts.geojson" -o "$out/gulf-parts.png" --json "$out/gulf-parts.json"
  echo "== check real data from $data"
  "$sm" check "$data/regions/matagorda_bay.geojson" --json "$out/matagorda-check.json"
  "$sm" convert "$data/regions/matagorda_bay.geojson" -o "$out/matagorda_bay.png"
  "$sm" check "$data/surfaces/rocker-arm.obj" --json "$out/rocker-arm-check.json"
  echo "== 3D (§2.2-2.3): the rocker arm tetrahedralized, guarded (exact ILP) and split into star-shaped parts"
  "$sm" tetmesh "$data/surfaces/rocker-arm.obj" -o "$out/rocker-arm.mesh" --json "$out/rocker-arm-tetmesh.json"
  "$sm" guard "$out/rocker-arm.mesh" -o "$out/rocker-arm-guards.json" -o "$out/rocker-arm-guards.vtu" \
    -o "$out/rocker-arm-guards.png" --json "$out/rocker-arm-guard-report.json"
  "$sm" star "$out/rocker-arm.mesh" --guards "$out/rocker-arm-guards.json" -o "$out/rocker-arm-parts.vtu" \
    -o "$out/rocker-arm-parts.png" --json "$out/rocker-arm-parts.json"
  echo "== 3D (ch. 4): the rocker arm's polycube domain (deformed, voxelized, optimised, planes merged)"
  "$sm" polycube "$data/surfaces/rocker-arm.obj" -o "$out/rocker-arm-polycube.obj" -o "$out/rocker-arm-polycube.png" \
    --deformed "$out/rocker-arm-pseudo-polycube.obj" --json "$out/rocker-arm-polycube.json"
  echo "== 3D (ch. 4-5): an all-hex mesh of the genus-3 model by polycube mapping"
  "$sm" hex "$data/surfaces/3holes.off" --hexes 25000 -o "$out/3holes-hex.vtu" -o "$out/3holes-hex.png" \
    --view 30,35 --polycube "$out/3holes-polycube.obj" --json "$out/3holes-hex.json"
  echo "== 3D (ch. 4-5): the rocker arm at the dissertation's 18k hexes"
  "$sm" hex "$data/surfaces/rocker-arm.obj" --hexes 18000 -o "$out/rocker-arm-hex.vtu" -o "$out/rocker-arm-hex.png" \
    --json "$out/rocker-arm-hex.json"
  # A model with defects: check reports them and exits 2, which the demo expects.
  if "$sm" check "$data/surfaces/tosca_centaur.off" --json "$out/centaur-check.json"; then
    echo "unexpected: centaur reported valid" >&2
    exit 1
  fi
fi

echo "== results in $out:"
ls -l "$out"
