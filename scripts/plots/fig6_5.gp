# Thesis Fig. 6.5 (§6.4, frame rate consistency): actual render time against the target
# c_targetTime, (a) run 1, (b) run 2 (or run 1 again when only one log is given).
set multiplot layout 2,1 title "Figure 6.5: actual vs target render time"
set xlabel "frame"
set ylabel "ms"
set yrange [0:*]
set title "(a) ".runName(1)
plot run1 using "frame":"actual_ms" with lines title "actual", run1 using "frame":"target_ms" with lines lw 2 lc 7 title "target"
set title "(b) ".runName(2)
plot run2 using "frame":"actual_ms" with lines title "actual", run2 using "frame":"target_ms" with lines lw 2 lc 7 title "target"
unset multiplot
