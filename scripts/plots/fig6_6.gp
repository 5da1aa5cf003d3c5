# Thesis Fig. 6.6 (§6.5, flicker): up toggles (positive) and down toggles (drawn negative, as in
# the thesis) per frame with the 35-frame moving average of all toggles, (a) walk-through,
# (b) drive-through (10x faster); (a) only without a drive log. Toggles as counted in
# player/STATS.md (culling-driven switches are not toggles).
if (hasDrive) { set multiplot layout 2,1 title "Figure 6.6: node toggles per frame" }
set xlabel "frame"
set ylabel "toggles"
set title (hasDrive ? "(a) walk-through" : "Figure 6.6 (a) walk-through: node toggles per frame (no drive log: no (b))")
plot walk using "frame":"up" with impulses lw 2 title "up", walk using "frame":"down" with impulses lw 2 title "down", \
     walk using "frame":"ma_toggles" with lines lw 2 lc 7 title "35-frame average"
if (hasDrive) {
  set title "(b) drive-through"
  plot drive using "frame":"up" with impulses lw 2 title "up", drive using "frame":"down" with impulses lw 2 title "down", \
       drive using "frame":"ma_toggles" with lines lw 2 lc 7 title "35-frame average"
  unset multiplot
}
