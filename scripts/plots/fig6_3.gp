# Thesis Fig. 6.3 (§6.2): the same as Fig. 6.2 for the second run (walk-through at ground
# level). With one run only: run 1's triangles per level, (a) counts, (b) percentages.
if (second) { data = run2; n = levels2; what = "nodes"; p = "pnodes"; name = "nodes drawn per level (run 2)" } \
else { data = run1; n = levels1; what = "tris"; p = "ptris"; name = "triangles drawn per level (run 1)" }
set multiplot layout 2,1 title "Figure 6.3: ".name
set xlabel "frame"
set ylabel what." drawn"
set yrange [0:*]
set title "(a)"
plot for [l=0:n-1] data using "frame":(column(sprintf("%s_l%d", what, l))) with lines lw 2 title sprintf("hlod_%d", l)
set ylabel "% of ".what." drawn"
set yrange [0:100]
set title "(b)"
plot for [l=0:n-1] data using "frame":(column(sprintf("%s_l%d", p, l))) with lines lw 2 title sprintf("hlod_%d", l)
unset multiplot
