# Thesis Fig. 6.2 (§6.2, detail management): the fly-through's (a) nodes drawn per HLOD level,
# (b) each level's percentage of the nodes drawn, per frame. Without a fly log: the walk's
# triangles per level instead (its nodes are Fig. 6.3).
if (hasFly) { data = fly; n = levelsFly; what = "nodes"; p = "pnodes"; name = "nodes drawn per level, fly-through" } \
else { data = walk; n = levelsWalk; what = "tris"; p = "ptris"; name = "triangles drawn per level, walk-through (no fly log)" }
set multiplot layout 2,1 title "Figure 6.2: ".name
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
