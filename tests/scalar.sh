#!/usr/bin/env bash
# The whole test suite built with the portable scalar code of the per-particle kernels
# (SEMLOC_FORCE_SCALAR=ON: the code a non-x86 build takes instead of the SSE2 paths, whose
# results are the same bits): configures and builds build-scalar/ (the benchmarks are not
# part of the suite), then runs every ctest entry there.   Usage: bash tests/scalar.sh
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${SEMLOC_SCALAR_DIR:-build-scalar}
[ -f "$dir/CMakeCache.txt" ] ||
    cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DSEMLOC_FORCE_SCALAR=ON \
          -DSEMLOC_BUILD_BENCHMARKS=OFF
cmake --build "$dir" -j2
# unit_size reads the sources, not the build: the plain build runs it.
ctest --test-dir "$dir" -j2 --output-on-failure -E "^unit_size$"
