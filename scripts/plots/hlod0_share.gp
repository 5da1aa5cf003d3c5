# Not a thesis figure: the hlod0 share (§4.2 second feedback loop, player/SELECTION.md) over time
# in multiples of c_targetTime, log scale, with its bounds [0.1, 20] x c_targetTime (player/feedback.h)
# and the frame time; (a) walk-through, (b) fly-through when given.
if (hasFly) { set multiplot layout 2,1 title "hlod0 share over time (second feedback loop)" }
set xlabel "frame"
set ylabel "x c_{targetTime}"
set logscale y
set yrange [0.05:40]
set title (hasFly ? "(a) walk-through" : "hlod0 share over time (second feedback loop), walk-through")
plot walk using "frame":(column("share_ms") / column("target_ms")) with lines lw 2 title "hlod0 share", \
     walk using "frame":(column("actual_ms") / column("target_ms")) with lines lc 3 title "actual / target", \
     0.1 with lines dt 2 lc 7 title "bounds", 20 with lines dt 2 lc 7 notitle, 1 with lines lc 8 notitle
if (hasFly) {
  set title "(b) fly-through"
  plot fly using "frame":(column("share_ms") / column("target_ms")) with lines lw 2 title "hlod0 share", \
       fly using "frame":(column("actual_ms") / column("target_ms")) with lines lc 3 title "actual / target", \
       0.1 with lines dt 2 lc 7 title "bounds", 20 with lines dt 2 lc 7 notitle, 1 with lines lc 8 notitle
  unset multiplot
}
