# Thesis Fig. 6.6 (§6.5, flicker): up toggles (positive) and down toggles (drawn negative,
# as in the thesis) per frame with the 35-frame moving average of all toggles, (a) run 1, (b) run 2.
set multiplot layout 2,1 title "Figure 6.6: node toggles per frame"
set xlabel "frame"
set ylabel "toggles"
set title "(a) ".runName(1)
plot run1 using "frame":"up" with impulses lw 2 title "up", run1 using "frame":"down" with impulses lw 2 title "down", \
     run1 using "frame":"ma_toggles" with lines lw 2 lc 7 title "35-frame average"
set title "(b) ".runName(2)
plot run2 using "frame":"up" with impulses lw 2 title "up", run2 using "frame":"down" with impulses lw 2 title "down", \
     run2 using "frame":"ma_toggles" with lines lw 2 lc 7 title "35-frame average"
unset multiplot
