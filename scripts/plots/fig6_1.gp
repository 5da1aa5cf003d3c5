# Thesis Fig. 6.1 (§6.1, memory management, §4.3): memory used over time by the walk-through.
# The thesis draws "memory utilization" in percent: (a) c_memory x sum(cost), the quantity the
# loader bounds, as a share of the memory budget (--memory), with the real bytes held beside it;
# (b) both in MiB. Without a budget only (b) is drawn.
set xlabel "time (s)"
set yrange [0:*]
if (budget > 0) {
  set multiplot layout 2,1 title "Figure 6.1: memory over time, walk-through (§4.3)"
  set title "(a) share of the memory budget (thesis units)"
  set ylabel "% of memory"
  plot walk using "time_s":"estimate_pct" with lines lw 2 title "c_{memory} x cost", \
       walk using "time_s":"resident_pct" with lines lw 1 dt 2 title "resident bytes"
  set title "(b) bytes"
} else {
  set title "Figure 6.1: memory over time, walk-through (§4.3; no --memory budget: MiB only)"
}
set ylabel "memory (MiB)"
plot walk using "time_s":"estimate_mib" with lines lw 2 title "c_{memory} x cost", \
     walk using "time_s":"resident_mib" with lines lw 1 dt 2 title "resident bytes"
if (budget > 0) { unset multiplot }
