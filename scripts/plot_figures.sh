#!/usr/bin/env bash
# Redraws thesis Figures 6.1-6.6 from `hlod play` statistics logs (columns: player/stats.h,
# player/STATS.md) as OUTDIR/fig6_1.png ... fig6_6.png, plus OUTDIR/hlod0_share.png (the second
# feedback loop's hlod0 share over time, not a thesis figure), with gnuplot (pngcairo).
#   usage: scripts/plot_figures.sh WALK.csv OUTDIR [FLY.csv [DRIVE.csv]]
# The thesis's runs: 6.1 and 6.4 a walk-through; 6.2 a fly-through, 6.3 a walk-through;
# 6.5 (a) walk-through, (b) fly-through; 6.6 (a) walk-through, (b) drive-through (10x faster).
# Without FLY.csv, 6.2 shows the walk's triangles per level and 6.5 has panel (a) only; without
# DRIVE.csv, 6.6 has panel (a) only. The script prints what each figure draws.
# Exit status: 0 written, 2 bad usage or unreadable/invalid log, 3 gnuplot missing.
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
die() { echo "plot_figures: $1" >&2; exit "${2:-2}"; }

[ $# -ge 2 ] && [ $# -le 4 ] || die "usage: plot_figures.sh WALK.csv OUTDIR [FLY.csv [DRIVE.csv]]"
walkLog="$1"; out="$2"; flyLog="${3:-}"; driveLog="${4:-}"
command -v gnuplot >/dev/null || die "gnuplot not found (Debian package gnuplot-nox)" 3

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# derive LOG TSV: the columns the figures need, by name, plus percent differences and
# 35-frame moving averages (thesis Fig. 6.4d, 6.6).
derive() {
  [ -f "$1" ] && [ -r "$1" ] || die "$1: cannot be read"
  awk -F, -v name="$1" -f "$here/plots/derive.awk" "$1" > "$2" || exit 2
}
levelsOf() { head -n1 "$1" | tr ' ' '\n' | grep -c '^nodes_l'; }
budgetOf() { sed -n 's/^# memory_budget_bytes: *\([0-9]*\).*/\1/p' "$1" | head -n1; }
derive "$walkLog" "$work/walk.tsv"
hasFly=0; hasDrive=0
if [ -n "$flyLog" ]; then derive "$flyLog" "$work/fly.tsv"; hasFly=1; else cp "$work/walk.tsv" "$work/fly.tsv"; fi
if [ -n "$driveLog" ]; then derive "$driveLog" "$work/drive.tsv"; hasDrive=1; else cp "$work/walk.tsv" "$work/drive.tsv"; fi
budget="$(budgetOf "$walkLog")"

mkdir -p "$out" || die "$out: cannot create the directory"
for fig in fig6_1 fig6_2 fig6_3 fig6_4 fig6_5 fig6_6 hlod0_share; do
  gnuplot -e "walk='$work/walk.tsv'; fly='$work/fly.tsv'; drive='$work/drive.tsv'; \
levelsWalk=$(levelsOf "$work/walk.tsv"); levelsFly=$(levelsOf "$work/fly.tsv"); \
hasFly=$hasFly; hasDrive=$hasDrive; budget=${budget:-0}; out='$work/$fig.png'" \
    "$here/plots/common.gp" "$here/plots/$fig.gp" 2> "$work/gnuplot.err" ||
    die "gnuplot failed on $fig: $(head -n 3 "$work/gnuplot.err" | tr '\n' ' ')"
  mv "$work/$fig.png" "$out/$fig.png"
done
echo "plot_figures: wrote $out/fig6_1.png ... fig6_6.png, $out/hlod0_share.png"
echo "  6.1: walk-through memory, MiB$([ "${budget:-0}" -gt 0 ] && echo " and % of the memory budget" || echo " (no --memory budget: no % panel)")"
echo "  6.2: $([ $hasFly = 1 ] && echo "fly-through, nodes per level" || echo "walk-through, triangles per level (no fly log)")"
echo "  6.3: walk-through, nodes per level; 6.4: walk-through estimates"
echo "  6.5: $([ $hasFly = 1 ] && echo "(a) walk-through, (b) fly-through" || echo "(a) walk-through only (no fly log)")"
echo "  6.6: $([ $hasDrive = 1 ] && echo "(a) walk-through, (b) drive-through" || echo "(a) walk-through only (no drive log)")"
