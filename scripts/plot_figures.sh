#!/usr/bin/env bash
# Redraws thesis Figures 6.1-6.6 from `hlod play` statistics logs (columns: player/stats.h,
# player/STATS.md) as OUTDIR/fig6_1.png ... fig6_6.png with gnuplot (pngcairo).
#   usage: scripts/plot_figures.sh LOG.csv OUTDIR [LOG2.csv]
# The thesis draws 6.2/6.3, 6.5(a)/(b) and 6.6(a)/(b) for two runs (walk-through, fly-through);
# LOG2 is the second run. Without it, 6.3 shows LOG's triangles per level (6.2 shows nodes)
# and the (b) panels repeat LOG.
# Exit status: 0 written, 2 bad usage or unreadable/invalid log, 3 gnuplot missing.
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
die() { echo "plot_figures: $1" >&2; exit "${2:-2}"; }

[ $# -eq 2 ] || [ $# -eq 3 ] || die "usage: plot_figures.sh LOG.csv OUTDIR [LOG2.csv]"
log1="$1"; out="$2"; log2="${3:-$1}"
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
derive "$log1" "$work/run1.tsv"
derive "$log2" "$work/run2.tsv"
levels1="$(levelsOf "$work/run1.tsv")"
levels2="$(levelsOf "$work/run2.tsv")"

mkdir -p "$out" || die "$out: cannot create the directory"
second=$([ $# -eq 3 ] && echo 1 || echo 0)
for n in 1 2 3 4 5 6; do
  gnuplot -e "run1='$work/run1.tsv'; run2='$work/run2.tsv'; levels1=$levels1; levels2=$levels2; second=$second; out='$work/fig6_$n.png'" \
    "$here/plots/common.gp" "$here/plots/fig6_$n.gp" 2> "$work/gnuplot.err" ||
    die "gnuplot failed on Figure 6.$n: $(head -n 3 "$work/gnuplot.err" | tr '\n' ' ')"
  mv "$work/fig6_$n.png" "$out/fig6_$n.png"
done
echo "plot_figures: wrote $out/fig6_1.png ... fig6_6.png"
