# Thesis Fig. 6.4 (§6.3, accuracy of the estimated render time, §4.2 feedback loop):
# (a) 100 (actual - estimate) / estimate without feedback (initial v_time), (b) with the
# feedback loop, (c) v_time, (d) 35-frame moving averages of (a) and (b). Negative = conservative
# (the frame took less than estimated), the thesis convention (§6.3 footnote 2).
set multiplot layout 2,2 title "Figure 6.4: estimated vs actual render time (walk-through)"
set xlabel "frame"
set ylabel "% difference"
set title "(a) without feedback"
plot walk using "frame":"pct_nofb" with lines title "no feedback"
set title "(b) with feedback"
plot walk using "frame":"pct_fb" with lines lc 2 title "feedback"
set title "(c) feedback variable v_{time}"
set ylabel "ms per unit cost"
plot walk using "frame":"v_time" with lines lc 3 title "v_{time}"
set title "(d) 35-frame moving average"
set ylabel "% difference"
plot walk using "frame":"ma_nofb" with lines lw 2 title "no feedback", \
     walk using "frame":"ma_fb" with lines lw 2 lc 2 title "feedback"
unset multiplot
