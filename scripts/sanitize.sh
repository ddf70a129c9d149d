#!/usr/bin/env bash
# Builds the module tests with AddressSanitizer + UndefinedBehaviorSanitizer and runs them
# all but a few: the Gulf of Mexico in 8 and 16 parts (185 s and 160 s under ASan, about 6 of
# CI's 45 minutes) and Matagorda Bay in 8 (55 s; CI took 45.1 of its 45 minutes with it). The
# same code runs sanitized on the Gulf in 2 parts and West Bay (Galveston) in 8, and the three
# run unsanitized in scripts/test.sh.
# The command-line tool and its end-to-end tests are left out (STRUCTMESH_CLI=OFF): the CLI
# is a thin layer over the modules tested here, its tests run in scripts/test.sh, and
# CI's budget did not hold both (the whole of .ci/run took 51 minutes with them).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
# OpenBLAS pinned to its AVX2 kernels where the CPU has them (why: in the script).
source "$root/scripts/pin-blas.sh"
"$root/scripts/install-deps.sh"
build_dir=${BUILD_DIR:-$root/build-asan}
# -O1 keeps the sanitized CGAL code fast enough; frame pointers and line tables (-g1) give
# readable reports. Full debug info (-g) cost 40% more compile time (measured on
# sample_partition.cpp: 112 s -> 67 s) in a build that took 26 of CI's 54 minutes.
cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DSTRUCTMESH_SANITIZE=ON -DSTRUCTMESH_WERROR=ON -DSTRUCTMESH_BENCH=OFF -DSTRUCTMESH_CLI=OFF
cmake --build "$build_dir" -j "$(nproc)"
cd "$build_dir"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# Left out as well (they run unsanitized in scripts/test.sh; 610 s of the 1,607 s of sanitized
# test time measured on 2026-12-02): sweeps that repeat code the other tests run sanitized --
# the Key partitioned at many sizes (193 s), the first CVT-GP bisection against the exact one
# (160 s), paving of random polygons (144 s) -- and the Natural Earth Gulf in 16 parts (113 s).
# And the closed dog's hex mesh (544 s sanitized, 54 s plain): CI took 54 minutes with it (36
# before). The unmerged retry it exercises runs sanitized on the torus (BuildPolycube.
# WithoutPlaneMerging*), the volumetric map and extraction on the other PolycubeHexMesh tests.
# And two polycube builds of data models (CI took 44 of its 45 minutes with them): genus one
# and three (90 s sanitized; the genus-three model's polycube is built sanitized by
# PolycubeHexMesh.GenusThreeModelFromTheDataSet, the torus's by the BuildPolycube tests) and the
# closed dog's thin ears (72 s; a part thinner than a voxel stays sanitized in
# BuildPolycube.CoversAPlateThinnerThanAVoxel). And fertility's hex mesh at 16k hexes (over
# 10 minutes sanitized beside another build, 31 s plain): the fresh starts of the worst
# cluster it exists for run sanitized in SmoothHexMesh.FreshStartsOfTheWorstCluster. And the
# screwdriver's and kitten_40k's flip-free maps (20-50 s plain each, the whole pipeline on
# data models): the surface smoothing runs sanitized in the SmoothSurfaceMap tests, the joint
# untangling in the UntangleTetMap ones.
# And three partition tests that repeat what others run sanitized (CI took 44.4 of its 45
# minutes with them; 210 s of sanitized test time): the pipe partitioned three times to
# compare (PartitionRegion.DeterministicAndThreadIndependent; ASan and UBSan see no races),
# the Key's CVT-GP at 32 parts (also in PartitionRegion.KeyAndPipeAllMethods), and the Gulf's
# lon/lat partition in 64 parts (its projection runs sanitized in RealCoastline's Gulf in 2).
# And the Key in 32 parts with polar layouts for its unplanned parts (85 s sanitized; CI took
# 43.4 of its 45 minutes with it): the layouts' code runs sanitized in the PolarBlockCandidates
# and PolarMesh tests, the Key's 32 parts are paved sanitized in Paving.KeyRegionIn32Parts and
# the whole pipeline runs sanitized on the coastlines (RealCoastline, ACreekNarrower...).
ctest --output-on-failure -j "$(nproc)" --timeout 900 \
  -E 'RealCoastline.*(gulf_of_mexico_(8|16|ne10m_16)|matagorda_bay_8)_parts|SamplePartition.EveryPartOfTheKeyIsEvenAtManySizes|ExactBisection.CvtGpFirstBisectionWithin15PercentOfExact|Paving.RandomPolygonsNeverFail|PolycubeHexMesh.ThinPartsFoldTheMergedMap.*|PolycubeHexMesh.FertilityAt16kHexesHasNoPoorHex|PolycubeHexMesh.ScrewdriverMapIsFlipFree.*|PolycubeHexMesh.Kitten40kMapIsFlipFree.*|BuildPolycube.DataModelsOfGenusOneAndThree|BuildPolycube.ClosedDogWithEarsThinnerThanAVoxel|PartitionRegion.(DeterministicAndThreadIndependent|CvtGpMeetsTheBalanceTolerance|LonLatGulfIsProjectedAndConnected)|MeshRegionQuads.KeyPartsWithoutAPlannedLayoutGetPolarBlocksBeforePaving'
