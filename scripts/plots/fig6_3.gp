# Thesis Fig. 6.3 (§6.2): the walk-through at ground level, (a) nodes drawn per HLOD level,
# (b) each level's percentage of the nodes drawn, per frame.
set multiplot layout 2,1 title "Figure 6.3: nodes drawn per level, walk-through"
set xlabel "frame"
set ylabel "nodes drawn"
set yrange [0:*]
set title "(a)"
plot for [l=0:levelsWalk-1] walk using "frame":(column(sprintf("nodes_l%d", l))) with lines lw 2 title sprintf("hlod_%d", l)
set ylabel "% of nodes drawn"
set yrange [0:100]
set title "(b)"
plot for [l=0:levelsWalk-1] walk using "frame":(column(sprintf("pnodes_l%d", l))) with lines lw 2 title sprintf("hlod_%d", l)
unset multiplot
