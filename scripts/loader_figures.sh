#!/usr/bin/env bash
# Varadhan & Manocha 2002 Figs. 9-11 in kind (issue 12 item 3; player/LOADER_RUNS.md): the
# loaders `vm` (prioritized prefetching, their OOCPre), `demand` (no prefetching, OOCNoPre) and
# `incore` (everything loaded first, Incore) replayed on the cost model with the synchronous
# loader and `--on-miss wait`, so that every demand fetch costs the disk model's time in the
# frame, exactly and repeatably.
#   usage: scripts/loader_figures.sh DB OUTDIR PATH...
# For each camera path:
#   1. the front: `demand` with no budget; F = the largest front (max of the front_bytes column,
#      decoded bytes of the drawn nodes). A footprint of k x F is the budget H + k x F, where H is
#      the hlod0 set (resident before any load, never evicted: the analogue of their skeleton,
#      which "does not account" in their footprint, §5.2);
#   2. Fig. 9, frame time per frame: vm, demand (footprint FIG9 x F, default 2) and incore
#      (INCORE=0: the vm run without its waits instead);
#   3. Fig. 10, demand-fetched bytes per frame against half the front: the same vm and demand runs;
#   4. Fig. 11, demand-fetched bytes as the footprint grows: vm and demand at 1, 2, 3, 4.4 x F.
# Writes OUTDIR/NAME-LOADER-xK.csv (NAME: the path file's name without .path), OUTDIR/summary.tsv
# (one line a run: total demand and prefetch bytes, frame times, waits) and OUTDIR/figN_NAME.png.
# Environment: HLOD (default build/hlod), PLAY_FLAGS (extra `hlod play` flags, e.g.
# "--model-ms-per-tri 0.00005 --frames 3000"), INCORE=0 skips the incore run (a database whose
# decoded size does not fit this machine's memory), FACTORS (default "1 2 3 4.4"), FIG9 (2).
# Exit status: 0 written, 1 a run failed, 2 bad usage or unreadable input, 3 gnuplot missing.
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
die() { echo "loader_figures: $1" >&2; exit "${2:-2}"; }

[ $# -ge 3 ] || die "usage: loader_figures.sh DB OUTDIR PATH..."
db="$1"; out="$2"; shift 2
hlod="${HLOD:-build/hlod}"
factors="${FACTORS:-1 2 3 4.4}"
fig9="${FIG9:-2}"
[ -x "$hlod" ] || die "$hlod: not an executable (set HLOD)"
[ -r "$db" ] || die "$db: cannot be read"
for p in "$@"; do [ -r "$p" ] || die "$p: cannot be read"; done
command -v gnuplot >/dev/null || die "gnuplot not found (Debian package gnuplot-nox)" 3
mkdir -p "$out" || die "$out: cannot create the directory"

# column CSV NAME...: the named columns of a `hlod play` log, space-separated, with a header.
columns() {
  awk -F, -v want="$2" -v name="$1" '
    /^#/ { next }
    !h { h = 1; n = split(want, w, " ")
         for (i = 1; i <= NF; i++) idx[$i] = i
         for (k = 1; k <= n; k++) if (!(w[k] in idx)) { print name ": no column " w[k] > "/dev/stderr"; exit 2 }
         print want; next }
    { line = ""; for (k = 1; k <= n; k++) line = line (k > 1 ? " " : "") $(idx[w[k]]); print line }' "$1"
}
maxOf() { columns "$1" "$2" | awk 'NR > 1 && $1 > m { m = $1 } END { printf "%.0f\n", m }'; }

# play NAME LOADER FACTOR BUDGET PATH: one synchronous run with --on-miss wait.
play() {
  local csv="$out/$1-$2-x$3.csv"
  echo "== $1: $2, footprint $3 x F = $4 bytes"
  # shellcheck disable=SC2086
  "$hlod" play "$db" --path "$5" --sync-loader --loader "$2" --on-miss wait --memory "$4" \
    --stats "$csv" --json "$out/$1-$2-x$3.json" ${PLAY_FLAGS:-} > "$out/$1-$2-x$3.txt" ||
    die "hlod play failed ($1, $2, x$3): see $out/$1-$2-x$3.txt" 1
  columns "$csv" "frame actual_ms wait_ms demand_bytes prefetch_bytes front_bytes wanted_missing" |
    awk -v run="$1 $2 $3 $4" 'NR > 1 { n++; ms += $2; if ($2 > mx) mx = $2; if ($3 > 0) w++; if ($3 > mw) mw = $3
                                       d += $4; p += $5; if ($6 > f) f = $6; miss += $7 }
      END { printf "%s %d %.0f %.0f %.0f %.3f %.3f %d %.3f %d\n", run, n, d, p, f, ms / n, mx, w, mw, miss }' \
    >> "$out/summary.tsv"
}

echo "path loader factor budget_bytes frames demand_bytes prefetch_bytes max_front_bytes mean_ms max_ms" \
  "frames_waiting max_wait_ms wanted_missing" > "$out/summary.tsv"
for path in "$@"; do
  name="$(basename "$path" .path)"
  "$hlod" play "$db" --path "$path" --sync-loader --sync-loads 0 --frames 1 --stats "$out/$name-hlod0.csv" \
    > /dev/null || die "hlod play failed ($name, hlod0 set)" 1
  hlod0="$(maxOf "$out/$name-hlod0.csv" resident_bytes)"
  play "$name" demand front 0 "$path"
  front="$(maxOf "$out/$name-demand-xfront.csv" front_bytes)"
  [ "$front" -gt 0 ] || die "$name: the front has no bytes" 1
  echo "   $name: largest front F = $front bytes, hlod0 set H = $hlod0 bytes"
  for k in $factors; do
    budget="$(awk -v k="$k" -v f="$front" -v h="$hlod0" 'BEGIN { printf "%.0f", h + k * f }')"
    play "$name" vm "$k" "$budget" "$path"
    play "$name" demand "$k" "$budget" "$path"
  done
  if [ "${INCORE:-1}" = 1 ]; then play "$name" incore all 0 "$path"; fi
  for fig in 9 10 11; do
    gnuplot -e "dir='$out'; name='$name'; fig9='$fig9'; factors='$factors'; incore=${INCORE:-1}; \
out='$out/fig${fig}_$name.png'" "$here/plots/vm_common.gp" "$here/plots/vm_fig$fig.gp" 2> "$out/gnuplot.err" ||
      die "gnuplot failed on fig $fig ($name): $(head -n 3 "$out/gnuplot.err" | tr '\n' ' ')" 1
  done
done
rm -f "$out/gnuplot.err"
column -t "$out/summary.tsv"
echo "loader_figures: wrote $out/summary.tsv and $out/fig{9,10,11}_*.png"
