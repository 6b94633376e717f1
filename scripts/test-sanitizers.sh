#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer, in its own build folder
# (build-asan/, -O1 with line tables, without the benchmarks and the examples; measured in CI's
# rehearsal of 8d5a880 on 2 idle cores: build and suite 1067 s, the suite 521 s of it, with
# .ci/run's exclusions). Leak detection is on; the one suppression (PCL's Poisson table) sits beside the Poisson call
# in src/geometry/coarse_mesh_estimation.cpp. Extra arguments go to ctest (e.g. -R CliBadInput).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${PCL_PATCHDICT_ASAN_BUILD_DIR:-$root/build-asan}"
jobs="${PCL_PATCHDICT_JOBS:-$(nproc 2>/dev/null || echo 2)}"

PCL_PATCHDICT_BUILD_DIR="$build_dir" bash "$root/scripts/build.sh" -DCMAKE_BUILD_TYPE=Sanitize \
  -DCMAKE_CXX_FLAGS_SANITIZE="-O1 -g1" -DCMAKE_C_FLAGS_SANITIZE="-O1 -g1" -DPCL_PATCHDICT_SANITIZE=ON \
  -DPCL_PATCHDICT_BUILD_BENCH=OFF -DPCL_PATCHDICT_BUILD_EXAMPLES=OFF
cd "$build_dir"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
# Open MPI's own allocations at MPI_Init / MPI_Finalize (the learn-over-ranks tests): suppressed by
# the frames that call them (scripts/lsan-mpi.supp).
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$root/scripts/lsan-mpi.supp:print_suppressions=0}"
ctest --output-on-failure -j "$jobs" --timeout 1200 "$@"
