#!/usr/bin/env bash
# Our Batch-OMP vs scikit-learn's orthogonal_mp_gram on the same dictionary and signals, one
# thread each (see bench/compare_omp_sklearn.py). Writes bench/results/omp_vs_sklearn.md.
#
#   bash bench/compare_omp_sklearn.sh [options of compare_omp_sklearn.py, e.g. --signals 2000]
#
# PCL_PATCHDICT_BUILD_DIR: build directory holding libpcl_patchdict.a (default: build).
set -euo pipefail

cd "$(dirname "$0")/.."
build_dir=${PCL_PATCHDICT_BUILD_DIR:-build}
# Debian's interpreter on purpose: the python3 first on PATH may be another install (pyenv here)
# that has neither the Debian sklearn nor numpy.
python=/usr/bin/python3

if ! "$python" -c 'import sklearn, numpy' 2>/dev/null; then
  echo "installing python3-sklearn and python3-numpy (Debian packages)" >&2
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo=sudo; fi
  export DEBIAN_FRONTEND=noninteractive
  # Stale package lists make install fail with 404s: refresh them then, and only then.
  $sudo apt-get install -y --no-install-recommends python3-sklearn python3-numpy ||
    { $sudo apt-get update && $sudo apt-get install -y --no-install-recommends python3-sklearn python3-numpy; }
fi

library="$build_dir/libpcl_patchdict.a"
if [ ! -f "$library" ]; then
  if [ ! -f "$build_dir/CMakeCache.txt" ]; then
    cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
  fi
  cmake --build "$build_dir" -j"$(nproc)" --target pcl_patchdict
elif [ -n "$(find src include -newer "$library" -print -quit)" ]; then
  echo "warning: $library is older than some of src/ include/; rebuild it to measure the current code" >&2
fi

# Only sparse_coding.o is pulled from the archive and it needs no PCL symbols, so Eigen, OpenMP
# and the library suffice. EIGEN_HAS_CXX17_OVERALIGN=0 must match the library's build (see
# CMakeLists.txt). No -march flags: the library is built for baseline x86-64 as well.
driver="$build_dir/omp_driver"
g++ -O2 -std=c++17 -fopenmp -Wall -Wextra -DNDEBUG -DEIGEN_HAS_CXX17_OVERALIGN=0 \
  -I include -isystem /usr/include/eigen3 \
  bench/omp_driver/omp_driver.cpp "$library" -o "$driver"

exec "$python" bench/compare_omp_sklearn.py --driver "$driver" --output bench/results/omp_vs_sklearn.md "$@"
