#!/usr/bin/env bash
# Optional comparison of `pcl_patchdict fill-holes --no-patches` with CGAL's
# triangulate_refine_and_fair_hole (Liepa's method as CGAL implements it). Not a dependency: it
# needs Debian's libcgal-dev (apt-get install libcgal-dev) and skips cleanly without it.
#
# usage: bench/compare_cgal_holes.sh HOLED1.ply GT1.ply [HOLED2.ply GT2.ply ...]
#   Each holed mesh is filled by both, timed (whole process, wall clock), and scored against its
#   ground truth with `pcl_patchdict eval` (symmetric surface RMS and Hausdorff in GT's unit cube;
#   over the whole surface, so only the holes differ between the two).
#   Holed/GT pairs can come from anywhere, e.g. ../shared/harness/cases.py (holes_<h>.ply, gt.ply).
# env: PCL_PATCHDICT_TOOL (default build/pcl_patchdict), OUT_DIR (default bench/results/cgal_holes)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
tool="${PCL_PATCHDICT_TOOL:-$root/build/pcl_patchdict}"
out="${OUT_DIR:-$root/bench/results/cgal_holes}"
if [ ! -f /usr/include/CGAL/Polygon_mesh_processing/triangulate_hole.h ]; then
  echo "compare_cgal_holes: libcgal-dev is not installed; nothing to compare (apt-get install libcgal-dev)" >&2
  exit 0
fi
if [ $# -lt 2 ] || [ $(($# % 2)) -ne 0 ]; then
  echo "usage: $0 HOLED.ply GT.ply [HOLED.ply GT.ply ...]" >&2
  exit 2
fi
[ -x "$tool" ] || { echo "compare_cgal_holes: build the tool first ($tool)" >&2; exit 1; }
mkdir -p "$out"
cgal="$out/cgal_fill_holes"
if [ ! -x "$cgal" ] || [ "$root/bench/cgal_fill_holes/cgal_fill_holes.cpp" -nt "$cgal" ]; then
  echo "compare_cgal_holes: compiling the CGAL filler (a few minutes)" >&2
  g++ -O2 -std=c++17 -DCGAL_EIGEN3_ENABLED -I/usr/include/eigen3 \
    "$root/bench/cgal_fill_holes/cgal_fill_holes.cpp" -o "$cgal" -lgmp -lmpfr
fi
surface() { python3 -c "import json,sys; print('%.4g' % json.load(sys.stdin)['surface']['$1'])"; }
echo "| input | ours: s | ours: RMS | ours: Hausdorff | CGAL: s | CGAL: RMS | CGAL: Hausdorff |"
echo "|---|---|---|---|---|---|---|"
while [ $# -gt 0 ]; do
  holed="$1" gt="$2"
  shift 2
  name="$(basename "$(dirname "$holed")")_$(basename "$holed" .ply)"
  start=$(date +%s.%N)
  "$tool" fill-holes "$holed" --no-patches -o "$out/${name}_ours.ply" --quiet
  ours_s=$(python3 -c "print(round($(date +%s.%N) - $start, 3))")
  start=$(date +%s.%N)
  "$cgal" "$holed" "$out/${name}_cgal.ply" > /dev/null
  cgal_s=$(python3 -c "print(round($(date +%s.%N) - $start, 3))")
  ours=$("$tool" eval "$gt" "$out/${name}_ours.ply" --json --quiet)
  theirs=$("$tool" eval "$gt" "$out/${name}_cgal.ply" --json --quiet)
  echo "| $name | $ours_s | $(echo "$ours" | surface rms) | $(echo "$ours" | surface hausdorff) |" \
       "$cgal_s | $(echo "$theirs" | surface rms) | $(echo "$theirs" | surface hausdorff) |"
done
