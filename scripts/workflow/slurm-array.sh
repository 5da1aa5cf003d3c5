#!/usr/bin/env bash
# hlod on Slurm without Snakemake (README "Beyond one machine"): one job splits the input, a job
# array builds the shards once the split succeeded (--dependency=afterok), and one job merges
# them once every task succeeded (a failed step cancels the jobs waiting for it:
# --kill-on-invalid-dep). Prints the three job ids, the merge's last.
#
#   scripts/workflow/slurm-array.sh INPUT DB SHARDS [SBATCH_OPTION...]
#   e.g. HLOD=/shared/bin/hlod THREADS=4 MEM_MB=4096 scripts/workflow/slurm-array.sh /shared/scan.ply /shared/scan.hlod 16 -p batch
#
# Environment: HLOD (the binary, default hlod on PATH), WORK (default DB.work: WORK/split,
# WORK/shards/blocks_A_B, WORK/logs), THREADS (cores per shard, default 1), MEM_MB (per job,
# default 2048), SPLIT_ARGS, BUILD_ARGS (extra options of hlod split / hlod build).
# Resuming: run the same command again. The split is skipped when WORK/split/manifest.json exists,
# and a task whose shard folder holds a shard.json newer than that manifest keeps it, so only
# the unfinished shards are built. Every path must be on a file system all nodes share.
set -euo pipefail

HLOD=${HLOD:-hlod}
THREADS=${THREADS:-1}
MEM_MB=${MEM_MB:-2048}

# The shard folders of WORK for SHARDS jobs: "TASK FIRST LAST" per line (at most the block count).
ranges() {
  python3 - "$1/split/manifest.json" "$2" <<'PY'
import json, sys
blocks = json.load(open(sys.argv[1]))["block_count"]
n = max(1, min(int(sys.argv[2]), blocks))
for i in range(n):
    print(i, i * blocks // n, (i + 1) * blocks // n)
PY
}

case "${1:-}" in
--shard-task)  # inside the array: WORK SHARDS
  read -r _ first last < <(ranges "$2" "$3" | awk -v t="$SLURM_ARRAY_TASK_ID" '$1 == t') || true
  [ -n "${first:-}" ] || { echo "task $SLURM_ARRAY_TASK_ID: no blocks (fewer blocks than shards)"; exit 0; }
  out="$2/shards/blocks_${first}_${last}"
  if [ "$out/shard.json" -nt "$2/split/manifest.json" ]; then echo "$out: finished earlier, kept"; exit 0; fi
  rm -rf "$out"
  # shellcheck disable=SC2086
  exec "$HLOD" build "$2/split" -o "$out" --shard --blocks "$first:$last" -j "$THREADS" \
    --memory-limit "${MEM_MB}M" --progress-json $BUILD_ARGS
  ;;
--merge-task)  # WORK SHARDS DB
  mapfile -t shards < <(ranges "$2" "$3" | awk -v w="$2" '{print w "/shards/blocks_" $2 "_" $3}')
  exec "$HLOD" merge "${shards[@]}" -o "$4" --progress-json
  ;;
esac

[ $# -ge 3 ] || { echo "usage: $0 INPUT DB SHARDS [SBATCH_OPTION...]" >&2; exit 2; }
input=$1 db=$2 shards=$3
shift 3
work=${WORK:-$db.work}
self=$(realpath "$0")
mkdir -p "$work/logs" "$work/shards"
export HLOD THREADS MEM_MB BUILD_ARGS="${BUILD_ARGS:-}"

dependency=()
if [ ! -f "$work/split/manifest.json" ]; then
  split=$(sbatch --parsable "$@" -J hlod-split -c 1 --mem "$MEM_MB" -o "$work/logs/split-%j.log" \
    --wrap "$(printf '%q ' "$HLOD" split "$input" -o "$work/split" --memory-limit "${MEM_MB}M" --progress-json) ${SPLIT_ARGS:-}")
  dependency=(--dependency="afterok:$split")
  echo "split job $split"
fi
# The block count is known after the split: the array has SHARDS tasks, those past the block
# count exit at once.
array=$(sbatch --parsable "$@" "${dependency[@]}" --kill-on-invalid-dep=yes -J hlod-shard --array="0-$((shards - 1))" -c "$THREADS" \
  --mem "$MEM_MB" -o "$work/logs/shard-%A_%a.log" "$self" --shard-task "$work" "$shards")
echo "shard array $array"
merge=$(sbatch --parsable "$@" --dependency="afterok:$array" --kill-on-invalid-dep=yes -J hlod-merge -c 1 --mem "$MEM_MB" \
  -o "$work/logs/merge-%j.log" "$self" --merge-task "$work" "$shards" "$db")
echo "merge job $merge"
