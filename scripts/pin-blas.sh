# Sourced by the test and benchmark scripts.
# Results depend on the BLAS kernels (CHOLMOD's supernodal factorisation calls them):
# OpenBLAS picks them by CPU, and its AVX-512 kernels round differently from its AVX2 ones.
# The closed dog's hex mesh at 10k hexes has its worst hex at 0.54 with the AVX2 kernels,
# 0.40 with the AVX-512 ones (0.14 before the smoothing's fresh starts; measured 2026-12-05,
# bench/results/hex_avx512.md). The scripts pin the AVX2 kernels where the CPU has them, so
# that a run gives the same meshes on every CI machine.
if grep -q avx2 /proc/cpuinfo 2>/dev/null; then export OPENBLAS_CORETYPE=${OPENBLAS_CORETYPE:-Haswell}; fi
