#!/usr/bin/env bash
# Benchmark (README "Beyond one machine"; not a test): how a build divides into shards. For INPUT
# it runs one whole build (-j 1), then `hlod split` once and, for each shard count N, the N shard
# builds one after another (-j 1 each, as N machines of one core would) and the merge, and
# prints per step the CPU seconds (user + sys), wall seconds and peak RSS (GNU time), the
# critical path (split + slowest shard + merge: the wall time on N machines) and whether the
# merged database equals the whole build.
# Usage: scripts/bench-shards.sh HLOD INPUT OUT_DIR "1 2 4" [OPTION...]   (OPTIONs go to split and build)
set -euo pipefail
hlod=$(realpath "$1") input=$2 out=$3 counts=$4
shift 4
mkdir -p "$out"
# Runs a step under GNU time; prints "cpu wall rss_mb".
measure() {
  local name=$1
  shift
  /usr/bin/time -f '%U %S %e %M' -o "$out/$name.time" "$@" > "$out/$name.log" 2>&1 || { tail "$out/$name.log"; exit 1; }
  awk '{printf "%.1f %.1f %.0f\n", $1 + $2, $3, $4 / 1024}' "$out/$name.time"
}
row() { printf '%-28s %9s %9s %9s\n' "$@"; }
row step cpu_s wall_s rss_mb
read -r c w m < <(measure whole "$hlod" build "$input" -o "$out/whole.hlod" -j 1 "$@")
row "whole build" "$c" "$w" "$m"
rm -rf "$out/work"
read -r sc sw sm < <(measure split "$hlod" split "$input" -o "$out/work" "$@")
row "split" "$sc" "$sw" "$sm"
blocks=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["block_count"])' "$out/work/manifest.json")
echo "blocks: $blocks"
for n in $counts; do
  total=$sc slowest=0 shards=()
  for ((i = 0; i < n; i++)); do
    first=$((i * blocks / n)) last=$(((i + 1) * blocks / n))
    rm -rf "$out/shard-$n-$i"
    read -r c w m < <(measure "shard-$n-$i" "$hlod" build "$out/work" -o "$out/shard-$n-$i" --shard --blocks "$first:$last" -j 1)
    row "  $n shards: $first:$last" "$c" "$w" "$m"
    total=$(echo "$total + $c" | bc) slowest=$(echo "if ($c > $slowest) $c else $slowest" | bc)
    shards+=("$out/shard-$n-$i")
  done
  read -r mc mw mm < <(measure "merge-$n" "$hlod" merge "${shards[@]}" -o "$out/merged-$n.hlod")
  row "  $n shards: merge" "$mc" "$mw" "$mm"
  same=differs
  cmp -s "$out/whole.hlod" "$out/merged-$n.hlod" && same=identical
  echo "  $n shards: total $(echo "$total + $mc" | bc) CPU-s, critical path $(echo "$sc + $slowest + $mc" | bc) CPU-s, database $same"
done
