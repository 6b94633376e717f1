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

runs=${LEARN_SCALING_RUNS:-3}
row() {  # label, command...: runs the command $runs times, reports the run of median wall time
  local label=$1
  shift
  local jsons=()
  for _ in $(seq "$runs"); do jsons+=("$("$@")"); done
  /usr/bin/python3 - "$label" "${jsons[@]}" <<'PY'
import json, sys
label, runs = sys.argv[1], sorted((json.loads(a) for a in sys.argv[2:]), key=lambda j: j["seconds"]["learn"])
j = runs[len(runs) // 2]
s = j["seconds"]["learn"]
r = j.get("round_seconds", {})
parts = " / ".join(f'{r[k]:.2f}' for k in ("read", "code", "exchange", "update")) if r else "–"
spread = f'{runs[0]["seconds"]["learn"]:.2f}–{runs[-1]["seconds"]["learn"]:.2f}'
coded = j.get("patches_coded_per_shard", [])
print(f'| {label} | {j.get("ranks", 1)} | {j.get("shards", 1)} | {j["batches"]} | {s:.2f} ({spread}) | '
      f'{j["patches_streamed"] / s:,.0f} | {parts} | {coded if coded else "–"} |')
PY
}

{
  echo "| run | ranks | shards | rounds | learn s: median (range of $runs) | patches/s | rank 0: read / code / exchange / update s | patches per shard |"
  echo "|---|---|---|---|---|---|---|---|"
  row "one process, 1 thread" "$tool" "${job[@]}" -o "$work/a.pdd" --threads 1
  row "one process, 2 threads" "$tool" "${job[@]}" -o "$work/b.pdd" --threads 2
  row "one process, 2 shards, 1 thread" "$tool" "${job[@]}" -o "$work/c.pdd" --shards 2 --threads 1
  row "mpirun -np 2, 1 thread each" "${mpirun[@]}" "$tool" "${job[@]}" -o "$work/d.pdd" --threads 1
  # Oversubscribed (4 threads on 2 cores): what not to do; OpenMP threads then wait on each other.
  row "mpirun -np 2, 2 threads each (oversubscribed)" "${mpirun[@]}" --bind-to none "$tool" "${job[@]}" -o "$work/e.pdd" --threads 2
} | tee bench/results/learn_scaling.md
if cmp -s "$work/c.pdd" "$work/d.pdd" && cmp -s "$work/c.pdd" "$work/e.pdd"; then
  echo "2 shards in one process and on 2 ranks (1 or 2 threads): the same .pdd byte for byte" | tee -a bench/results/learn_scaling.md
else
  echo "learn_scaling: 2 shards in one process and on 2 ranks gave different dictionaries" >&2
  exit 1
fi
