#!/usr/bin/env bash
# The README's test command: install what is missing, build, run the whole test suite with ctest.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${PCL_PATCHDICT_BUILD_DIR:-$root/build}"
jobs="${PCL_PATCHDICT_JOBS:-$(nproc 2>/dev/null || echo 2)}"

bash "$root/scripts/build.sh" "$@"
cd "$build_dir"
ctest --output-on-failure -j "$jobs"
