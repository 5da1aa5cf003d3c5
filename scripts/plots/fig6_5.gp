# Thesis Fig. 6.5 (§6.4, frame rate consistency): actual render time against the target
# c_targetTime for (a) the walk-through and (b) the fly-through; (a) only without a fly log.
if (hasFly) { set multiplot layout 2,1 title "Figure 6.5: actual vs target render time" }
set xlabel "frame"
set ylabel "ms"
set yrange [0:*]
set title (hasFly ? "(a) walk-through" : "Figure 6.5 (a) walk-through: actual vs target render time (no fly log: no (b))")
plot walk using "frame":"actual_ms" with lines title "actual", walk using "frame":"target_ms" with lines lw 2 lc 7 title "target"
if (hasFly) {
  set title "(b) fly-through"
  plot fly using "frame":"actual_ms" with lines title "actual", fly using "frame":"target_ms" with lines lw 2 lc 7 title "target"
  unset multiplot
}
