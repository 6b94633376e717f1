#!/usr/bin/env bash
# Scaling of `learn` over shards and MPI ranks on this machine: the same inputs learned by one
# process (1 and 2 threads) and by `mpirun -np 2` (one shard per rank, one thread each), with
# patches/s and where rank 0's rounds went (read, code, exchange, update). The cost model of
# docs/results.md ("Learning on several ranks") is checked against these points.
#
#   bash bench/learn_scaling.sh [INPUTS...]     (default: the .pds of ../shared/data/meshes, made once)
#
# PCL_PATCHDICT_BUILD_DIR: build directory (default: build). Writes bench/results/learn_scaling.md.
set -euo pipefail
cd "$(dirname "$0")/.."
tool="${PCL_PATCHDICT_BUILD_DIR:-build}/pcl_patchdict"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

if [ $# -gt 0 ]; then
  inputs=("$@")
else
  meshes=../shared/data/meshes
  [ -d "$meshes" ] || { echo "learn_scaling: no inputs given and no $meshes" >&2; exit 1; }
  inputs=()
  for mesh in "$meshes"/*.obj "$meshes"/*.off; do
    out="$work/$(basename "${mesh%.*}").pds"
    "$tool" patches "$mesh" -o "$out" --quiet
    inputs+=("$out")
  done
fi
job=(learn "${inputs[@]}" --atoms 100 --sparsity 8 --batch 512 --iterations 3 --json --quiet)
mpirun=(mpirun --oversubscribe -np 2)
[ "$(id -u)" -eq 0 ] && mpirun=(mpirun --allow-run-as-root --oversubscribe -np 2)

row() {  # label, json
  /usr/bin/python3 - "$1" "$2" <<'PY'
import json, sys
label, j = sys.argv[1], json.loads(sys.argv[2])
s = j["seconds"]["learn"]
r = j.get("round_seconds", {})
parts = " / ".join(f'{r[k]:.2f}' for k in ("read", "code", "exchange", "update")) if r else "–"
print(f'| {label} | {j.get("ranks", 1)} | {j.get("shards", 1)} | {j["batches"]} | {s:.2f} | '
      f'{j["patches_streamed"] / s:,.0f} | {parts} |')
PY
}

{
  echo "| run | ranks | shards | rounds | learn s | patches/s | rank 0: read / code / exchange / update s |"
  echo "|---|---|---|---|---|---|---|"
  row "one process, 1 thread" "$("$tool" "${job[@]}" -o "$work/a.pdd" --threads 1)"
  row "one process, 2 threads" "$("$tool" "${job[@]}" -o "$work/b.pdd" --threads 2)"
  row "one process, 2 shards, 1 thread" "$("$tool" "${job[@]}" -o "$work/c.pdd" --shards 2 --threads 1)"
  row "mpirun -np 2, 1 thread each" "$("${mpirun[@]}" "$tool" "${job[@]}" -o "$work/d.pdd" --threads 1)"
  row "mpirun -np 2, 2 threads each" "$("${mpirun[@]}" --bind-to none "$tool" "${job[@]}" -o "$work/e.pdd" --threads 2)"
} | tee bench/results/learn_scaling.md
if cmp -s "$work/c.pdd" "$work/d.pdd" && cmp -s "$work/c.pdd" "$work/e.pdd"; then
  echo "2 shards in one process and on 2 ranks (1 or 2 threads): the same .pdd byte for byte" | tee -a bench/results/learn_scaling.md
else
  echo "learn_scaling: 2 shards in one process and on 2 ranks gave different dictionaries" >&2
  exit 1
fi
