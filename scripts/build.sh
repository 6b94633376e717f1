#!/usr/bin/env bash
# Installs missing dependencies, then configures and builds (Release) into build/.
# Extra arguments go to the CMake configure step, e.g. scripts/build.sh -DPCL_PATCHDICT_SANITIZE=ON
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${PCL_PATCHDICT_BUILD_DIR:-$root/build}"
jobs="${PCL_PATCHDICT_JOBS:-$(nproc 2>/dev/null || echo 2)}"

bash "$root/scripts/install-deps.sh"
if [ ! -f "$build_dir/CMakeCache.txt" ] || [ $# -gt 0 ]; then
  cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@" >&2
fi
# PCL_PATCHDICT_TARGET limits the build to one target (the ./pcl_patchdict wrapper builds only the tool).
cmake --build "$build_dir" -j "$jobs" ${PCL_PATCHDICT_TARGET:+--target "$PCL_PATCHDICT_TARGET"} >&2
