#!/usr/bin/env bash
# Installs the build dependencies from Debian 12 packages, skipping what is already installed.
# PCL 1.13 (libpcl-dev) brings Boost, Eigen 3.4, FLANN 1.9 and VTK 9.1 with it.
set -euo pipefail

# libopenmpi-dev + openmpi-bin: learn over MPI ranks (PCL's VTK pulls them in today; named so it stays so).
# doxygen: the API reference (`cmake --build build --target doc`; no Graphviz needed).
packages=(g++ cmake make libpcl-dev libgtest-dev libbenchmark-dev zlib1g-dev libopenmpi-dev openmpi-bin doxygen)
# --bench: also what bench/reproduce.py runs with (Python for the scripts, Draco for the comparison;
# numpy, scipy and pcl-tools — PCL's MLS and PCD converter — for bench/real_scans.py).
if [ "${1:-}" = "--bench" ]; then
  packages+=(python3 draco python3-numpy python3-scipy pcl-tools)
fi

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all dependencies present" >&2
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
  sudo=()
elif command -v sudo >/dev/null 2>&1; then
  sudo=(sudo)
else
  echo "install-deps: need root (or sudo) to install: ${missing[*]}" >&2
  exit 1
fi

echo "install-deps: installing ${missing[*]}" >&2
# --no-install-recommends keeps the PCL install to ~400 packages; cmake then needs make explicitly.
"${sudo[@]}" apt-get update -q
DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
