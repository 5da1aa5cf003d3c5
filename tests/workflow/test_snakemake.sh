#!/usr/bin/env bash
# The Snakemake workflow (scripts/workflow/Snakefile) run locally with `snakemake -c2` on the
# sample city: the database equals a single `hlod build`, the split and merge speak
# --progress-json, and an interrupted run resumes from its finished shards (a first run that
# stops after the split and one shard; the second run builds only the other shards), also after
# snakemake and its jobs are killed with SIGKILL.
# Usage: test_snakemake.sh HLOD_BINARY SOURCE_DIR
set -euo pipefail
hlod=$(realpath "$1")
src=$(realpath "$2")
command -v snakemake >/dev/null || { echo "FAIL: snakemake not installed (bash scripts/install-deps.sh)"; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
input="$src/samples/city"
smk() { snakemake -s "$src/scripts/workflow/Snakefile" -c2 --directory "$tmp" "$@" \
          --config input="$input" db="$tmp/city.hlod" work="$tmp/w" shards=3 hlod="$hlod" > "$tmp/smk.log" 2>&1 \
        || { cat "$tmp/smk.log"; echo "FAIL: snakemake $*"; exit 1; }; }

# Absurd config values: refused with their reason before any job (shards=0 or -1 ran one shard,
# 2.5 two, until stop 45).
for bad in shards=0 shards=-1 shards=2.5 shards=abc threads=0 mem_mb=-1; do
  if snakemake -s "$src/scripts/workflow/Snakefile" -n -c1 --directory "$tmp" \
       --config input="$input" db="$tmp/bad.hlod" hlod="$hlod" "$bad" > "$tmp/bad.log" 2>&1; then
    echo "FAIL: config $bad accepted"; exit 1
  fi
  grep -q "config ${bad%%=*}=.*: expected a whole number >= 1" "$tmp/bad.log" || { cat "$tmp/bad.log"; echo "FAIL: config $bad: no reason"; exit 1; }
done
snakemake -s "$src/scripts/workflow/Snakefile" -n -c1 --directory "$tmp" --config db="$tmp/bad.hlod" > "$tmp/bad.log" 2>&1 && exit 1
grep -q "config input: required" "$tmp/bad.log" || { cat "$tmp/bad.log"; echo "FAIL: missing input: no reason"; exit 1; }
[ ! -e "$tmp/bad.hlod" ] && [ ! -e "$tmp/bad.hlod.work" ] || { echo "FAIL: a refused config wrote files"; exit 1; }

"$hlod" build "$input" -o "$tmp/one.hlod" -j 2 > "$tmp/one.log"

# Interrupted: the split and the first shard only.
smk "$tmp/w/split"
blocks=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["block_count"])' "$tmp/w/split/manifest.json")
[ "$blocks" -ge 3 ] || { echo "FAIL: sample city split into $blocks blocks, expected >= 3"; exit 1; }
first="$tmp/w/shards/blocks_0_$((blocks / 3))"
smk "$first"
[ -f "$first/shard.json" ] || { echo "FAIL: $first/shard.json missing"; exit 1; }
[ ! -e "$tmp/city.hlod" ] || { echo "FAIL: database written by a partial run"; exit 1; }
stamp=$(stat -c %.9Y "$first/shard.json")
sleep 1

# Resumed: the other two shards and the merge.
smk --rerun-incomplete
[ "$(stat -c %.9Y "$first/shard.json")" = "$stamp" ] || { echo "FAIL: the finished shard was built again"; exit 1; }
grep -Eq '^shard +2 ' "$tmp/smk.log" || { cat "$tmp/smk.log"; echo "FAIL: the resumed run should build 2 shards"; exit 1; }
[ "$(ls "$tmp/w/shards" | wc -l)" = 3 ] || { echo "FAIL: expected 3 shards"; ls "$tmp/w/shards"; exit 1; }
cmp "$tmp/one.hlod" "$tmp/city.hlod" || { echo "FAIL: workflow database differs from a single build"; exit 1; }

# The line stream of every step: JSON progress lines from split, shards and merge.
for log in split merge "shard_0_$((blocks / 3))"; do
  grep -q '^{"stage":' "$tmp/w/logs/$log.log" || { cat "$tmp/w/logs/$log.log"; echo "FAIL: no --progress-json lines in $log.log"; exit 1; }
done

# Nothing left to do: a third run builds nothing.
smk --dry-run
grep -q "Nothing to be done" "$tmp/smk.log" || { cat "$tmp/smk.log"; echo "FAIL: a finished workflow wants to run again"; exit 1; }
# Killed hard (SIGKILL to snakemake and its jobs) once a shard has finished: --unlock, then the
# rerun with --rerun-incomplete completes the database, identical again.
rm -rf "$tmp/w/shards" "$tmp/city.hlod"
setsid snakemake -s "$src/scripts/workflow/Snakefile" -c1 --directory "$tmp" \
  --config input="$input" db="$tmp/city.hlod" work="$tmp/w" shards=3 hlod="$hlod" > "$tmp/killed.log" 2>&1 &
victim=$!
for _ in $(seq 600); do
  compgen -G "$tmp/w/shards/*/shard.json" > /dev/null && break
  sleep 0.1
done
kill -9 -- "-$victim" 2>/dev/null || true
wait "$victim" 2>/dev/null || true
[ ! -e "$tmp/city.hlod" ] || echo "note: the killed run had finished before the kill (a loaded machine)"
smk --unlock
smk --rerun-incomplete
cmp "$tmp/one.hlod" "$tmp/city.hlod" || { echo "FAIL: database after a killed run differs from a single build"; exit 1; }

echo "OK: snakemake -c2, $blocks blocks in 3 shards, database identical to a single build ($(stat -c %s "$tmp/city.hlod") bytes), resumed from a finished shard and after a kill -9"
