#!/usr/bin/env bash
# Installs exactly the Debian 12 packages structmesh's build, tests and demo need.
# Skips everything when all are present; runs `apt-get update` once before installing.
set -euo pipefail

packages=(
  cmake g++ ninja-build pkg-config          # build
  libeigen3-dev libcgal-dev libtbb-dev      # geometry, exact predicates, threads
  libcli11-dev nlohmann-json3-dev           # command line, JSON reports
  libpng-dev zlib1g-dev                     # PNG pictures, compressed VTU
  libmetis-dev coinor-libcbc-dev            # graph partitioning engine, MILP (--method exact)
  liblbfgspp-dev                            # quasi-Newton minimiser of the L_p-CVT energy
  libopenmpi-dev openmpi-bin                # distributed quad meshing (mpirun structmesh quad2d)
  libtet1.5-dev libembree-dev               # tetrahedralization (TetGen), visibility rays (Embree 3)
  libsuitesparse-dev libopenblas0-pthread   # CHOLMOD (sparse Cholesky of the volumetric map) on an optimised BLAS
  libgtest-dev libbenchmark-dev             # tests, benchmarks
  libgmsh-dev gmsh                          # oracle: Gmsh reads our .msh; makes a hex mesh for tests
  python3-vtk9                              # oracle: VTK's vtkMeshQuality (Verdict)
  clang libclang-rt-14-dev clang-format     # libFuzzer + sanitizers for the fuzz pass; style check
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
[[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
