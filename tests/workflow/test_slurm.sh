#!/usr/bin/env bash
# Opt-in (HLOD_SLURM_TEST=1, as root; README "Beyond one machine"): a one-node Slurm started by this
# script (its own munged, slurmctld and slurmd on ports 16817/16818, everything under a temporary
# folder, stopped at the end), then the sample city built (1) by the Snakemake workflow in cluster
# mode submitting every step with sbatch and (2) by the sbatch --array recipe
# (scripts/workflow/slurm-array.sh), resumed once after losing a shard. Both databases must equal
# a single `hlod build`. Installs slurm-wlm and munge when missing (scripts/install-deps.sh --slurm).
# Usage: HLOD_SLURM_TEST=1 test_slurm.sh HLOD_BINARY SOURCE_DIR
set -euo pipefail
[ "${HLOD_SLURM_TEST:-0}" = 1 ] || { echo "skipped: set HLOD_SLURM_TEST=1 (as root) to start a one-node Slurm and run it"; exit 77; }
[ "$(id -u)" = 0 ] || { echo "FAIL: the Slurm test starts munged, slurmctld and slurmd: run it as root"; exit 1; }
hlod=$(realpath "$1")
src=$(realpath "$2")
bash "$src/scripts/install-deps.sh" --slurm
tmp=$(mktemp -d /tmp/hlod-slurm-XXXXXX)
chmod 755 "$tmp"
host=$(hostname -s)
export SLURM_CONF="$tmp/slurm.conf"

stop() {
  for pid in "$tmp/slurmd.pid" "$tmp/slurmctld.pid" "$tmp/munged.pid"; do
    [ -s "$pid" ] && kill "$(cat "$pid")" 2>/dev/null || true
  done
  sleep 1
  rm -rf "$tmp"
}
trap stop EXIT
fail() { echo "FAIL: $*"; for f in "$tmp"/*.log; do echo "== $f"; tail -n 20 "$f"; done; exit 1; }

# MUNGE with a key and socket of its own, so that a munged already running is left alone.
mungekey --create --keyfile="$tmp/munge.key" --force
chmod 600 "$tmp/munge.key"
munged --force --key-file="$tmp/munge.key" --socket="$tmp/munge.sock" --pid-file="$tmp/munged.pid" \
  --log-file="$tmp/munged.log" --seed-file="$tmp/munged.seed"

mem=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 - 1024 ))
cat > "$SLURM_CONF" <<CONF
ClusterName=hlodtest
SlurmctldHost=$host
SlurmctldPort=16817
SlurmdPort=16818
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$tmp/munge.sock
SlurmUser=root
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/slurmctld.log
SlurmdLogFile=$tmp/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
ReturnToService=2
NodeName=$host CPUs=$(nproc) RealMemory=$mem State=UNKNOWN
PartitionName=hlod Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
mkdir -p "$tmp/state" "$tmp/spool"
slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF"
for _ in $(seq 60); do
  [ "$(sinfo -h -o %T 2>/dev/null)" = idle ] && break
  sleep 1
done
[ "$(sinfo -h -o %T)" = idle ] || fail "the node did not come up: $(sinfo 2>&1)"
echo "slurm up: $(sinfo -h -o '%P %D %c %m %T')"

input="$src/samples/city"
"$hlod" build "$input" -o "$tmp/one.hlod" -j 2 > "$tmp/one.out"

# (1) Snakemake's cluster mode: every job of the workflow goes through sbatch.
( cd "$tmp" && snakemake -s "$src/scripts/workflow/Snakefile" -j 3 --latency-wait 30 \
    --cluster "sbatch --parsable -c {threads} --mem {resources.mem_mb} -o $tmp/snakemake-job-%j.out" \
    --config input="$input" db="$tmp/smk.hlod" work="$tmp/smk" shards=3 mem_mb=1024 hlod="$hlod" > "$tmp/snakemake.log" 2>&1 ) \
  || fail "snakemake --cluster sbatch"
jobs=$(ls "$tmp"/snakemake-job-*.out | wc -l)
[ "$jobs" = 5 ] || fail "expected 5 Slurm jobs (split, 3 shards, merge), saw $jobs"
cmp "$tmp/one.hlod" "$tmp/smk.hlod" || fail "snakemake on Slurm: database differs from a single build"
echo "snakemake --cluster sbatch: $jobs Slurm jobs, database identical"

# (2) The sbatch --array recipe; the merge job's id is its last line.
wait_for() {  # JOBID: until it leaves the queue; its final state
  for _ in $(seq 300); do
    state=$(scontrol show job "$1" 2>/dev/null | grep -o 'JobState=[A-Z]*' | cut -d= -f2 || true)
    case "$state" in PENDING|RUNNING|CONFIGURING|COMPLETING|"") sleep 1 ;; *) echo "$state"; return ;; esac
  done
  echo TIMEOUT
}
recipe() { HLOD="$hlod" MEM_MB=1024 WORK="$tmp/arr" bash "$src/scripts/workflow/slurm-array.sh" "$input" "$tmp/arr.hlod" 3 > "$tmp/recipe.out" 2>&1 \
             || fail "slurm-array.sh"; tail -n 1 "$tmp/recipe.out" | awk '{print $3}'; }
merge=$(recipe)
[ "$(wait_for "$merge")" = COMPLETED ] || fail "array recipe: merge job $merge did not complete"
cmp "$tmp/one.hlod" "$tmp/arr.hlod" || fail "sbatch --array: database differs from a single build"
echo "sbatch --array + --dependency=afterok: database identical"

# Resumed: one shard lost; the rerun keeps the split and the two other shards.
rm -rf "$tmp/arr/shards/blocks_0_3" "$tmp/arr.hlod"
merge=$(recipe)
grep -q "split job" "$tmp/recipe.out" && fail "the resumed recipe split again"
[ "$(wait_for "$merge")" = COMPLETED ] || fail "resumed array recipe: merge job $merge did not complete"
kept=$(grep -l "finished earlier, kept" "$tmp"/arr/logs/shard-*.log | wc -l)
[ "$kept" = 2 ] || fail "the resumed recipe should keep 2 finished shards, kept $kept"
cmp "$tmp/one.hlod" "$tmp/arr.hlod" || fail "resumed sbatch --array: database differs from a single build"
echo "OK: one-node Slurm ($host, $(nproc) CPUs): snakemake --cluster and sbatch --array (resumed after losing a shard) equal a single build"
