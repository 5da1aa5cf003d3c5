# Varadhan & Manocha 2002 Fig. 9: frame time per frame without prefetching (demand, their
# OOCNoPre), with it (vm, OOCPre) and in core (Incore), at a footprint of fig9 x the largest
# front. --on-miss wait puts the disk model's fetch time in the frame: misses are the spikes.
set title sprintf("Fig. 9 in kind: frame time, %s (footprint %s x largest front)", name, fig9)
set xlabel "frame"
set ylabel "frame time (ms)"
set yrange [0:*]
if (incore) {
  plot logf("demand", fig9) using "frame":"actual_ms" with lines lw 1 lc rgb "blue" title "demand (OOCNoPre)", \
       logf("vm", fig9) using "frame":"actual_ms" with lines lw 1 lc rgb "red" title "vm (OOCPre)", \
       logf("incore", "all") using "frame":"actual_ms" with lines lw 1 lc rgb "black" title "incore"
} else {
  # No incore run (INCORE=0): the vm run's drawing time alone (actual - wait) stands in for it;
  # the feedback loops see only the drawing time, so the fronts are alike.
  plot logf("demand", fig9) using "frame":"actual_ms" with lines lw 1 lc rgb "blue" title "demand (OOCNoPre)", \
       logf("vm", fig9) using "frame":"actual_ms" with lines lw 1 lc rgb "red" title "vm (OOCPre)", \
       logf("vm", fig9) using "frame":(column("actual_ms") - column("wait_ms")) with lines lw 1 lc rgb "black" \
         title "vm without its waits (no incore run)"
}
