# Varadhan & Manocha 2002 Fig. 10: bytes fetched on demand (their Stage II) per frame, without
# (demand) and with (vm) prefetching, against half the front's size (the black plot); (b) the
# same bytes summed from the first frame, which shows the ratio the per-frame plot hides.
set multiplot layout 2,1 title sprintf("Fig. 10 in kind: demand-fetched bytes, %s (footprint %s x largest front)", name, fig9)
set xlabel "frame"
set ylabel "MB (10^6 bytes)"
set yrange [0:*]
set title "(a) per frame"
plot logf("vm", fig9) using "frame":(column("front_bytes") / 2e6) with lines lw 1 lc rgb "black" title "front / 2", \
     logf("demand", fig9) using "frame":(column("demand_bytes") / 1e6) with impulses lw 1 lc rgb "blue" title "demand (OOCNoPre)", \
     logf("vm", fig9) using "frame":(column("demand_bytes") / 1e6) with impulses lw 1 lc rgb "red" title "vm (OOCPre)"
set title "(b) summed over the frames so far"
acc = 0
plot logf("demand", fig9) using "frame":(acc = ($0 == 0 ? 0 : acc) + column("demand_bytes") / 1e6) with lines lw 2 lc rgb "blue" title "demand (OOCNoPre)", \
     logf("vm", fig9) using "frame":(acc = ($0 == 0 ? 0 : acc) + column("demand_bytes") / 1e6) with lines lw 2 lc rgb "red" title "vm (OOCPre)"
unset multiplot
