#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (build-fuzz/) and fuzzes each for SECONDS (default 60),
# starting from the seed corpus in fuzz/corpus/<target>/. New inputs go to build-fuzz/corpus/<target>/
# (not the repository); crashes to build-fuzz/findings/<target>/. Prints executions, coverage and
# findings per target, and appends them to build-fuzz/fuzz-log.tsv.
#   scripts/fuzz.sh [SECONDS] [TARGET...]     e.g. scripts/fuzz.sh 600 pdc ply
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${PCL_PATCHDICT_FUZZ_BUILD_DIR:-$root/build-fuzz}"
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(ply obj off stl pcd pdd pds pdc pdk index sensor)

if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ is needed (apt-get install clang)" >&2
  exit 1
fi
bash "$root/scripts/install-deps.sh"
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
  CC=clang CXX=clang++ cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DPCL_PATCHDICT_FUZZ=ON -DPCL_PATCHDICT_BUILD_TESTS=OFF >&2
fi
cmake --build "$build_dir" -j "$(nproc)" --target $(printf 'fuzz_%s ' "${targets[@]}") >&2

# PCL's Poisson table is never freed (see coarse_mesh_estimation.cpp); nothing else is suppressed.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
log="$build_dir/fuzz-log.tsv"
[ -f "$log" ] || printf 'date\tcommit\ttarget\tseconds\texecs\tcov\tft\tcorpus\tfindings\n' >"$log"
commit="$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)"
status=0
for t in "${targets[@]}"; do
  corpus="$build_dir/corpus/$t"
  findings="$build_dir/findings/$t"
  mkdir -p "$corpus" "$findings"
  out="$build_dir/fuzz_$t.log"
  # -rss_limit_mb: the readers must refuse huge declared sizes before allocating them.
  "$build_dir/fuzz/fuzz_$t" "$corpus" "$root/fuzz/corpus/$t" -max_total_time="$seconds" \
    -max_len=65536 -rss_limit_mb=2048 -timeout=30 -artifact_prefix="$findings/" -print_final_stats=1 \
    >"$out" 2>&1 || status=1
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$out" | grep -o '[0-9]*$' || echo 0)
  cov=$(grep -o 'cov: [0-9]*' "$out" | tail -1 | grep -o '[0-9]*' || echo 0)
  ft=$(grep -o 'ft: [0-9]*' "$out" | tail -1 | grep -o '[0-9]*' || echo 0)
  n_corpus=$(find "$corpus" -type f | wc -l)
  n_findings=$(find "$findings" -type f | wc -l)
  printf '%-6s %6ss  execs %-10s cov %-6s ft %-6s corpus %-5s findings %s\n' "$t" "$seconds" "$execs" "$cov" "$ft" \
    "$n_corpus" "$n_findings"
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$(date -u +%FT%TZ)" "$commit" "$t" "$seconds" "$execs" "$cov" "$ft" \
    "$n_corpus" "$n_findings" >>"$log"
done
exit $status
