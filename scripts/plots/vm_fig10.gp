# Varadhan & Manocha 2002 Fig. 10: bytes fetched on demand (their Stage II) per frame, without
# (demand) and with (vm) prefetching, against half the front's size (the black plot); (b) the
# same bytes summed from the first frame, which shows the ratio the per-frame plot hides. Fetched
# bytes are stored (Draco/JPEG) bytes, the front decoded bytes: (a) draws them on two axes.
set multiplot layout 2,1 title sprintf("Fig. 10 in kind: demand-fetched bytes, %s (footprint %s x largest front)", name, fig9)
set xlabel "frame"
set ylabel "MB (10^6 bytes)"
set yrange [0:*]
set title "(a) per frame: fetched (stored bytes, left axis) and half the front (decoded bytes, right axis)"
set ylabel "MB fetched (10^6 stored bytes)"
set y2label "MB (10^6 decoded bytes)"
set y2range [0:*]
set y2tics
plot logf("vm", fig9) using "frame":(column("front_bytes") / 2e6) axes x1y2 with lines lw 1 lc rgb "black" title "front / 2 (decoded, right axis)", \
     logf("demand", fig9) using "frame":(column("demand_bytes") / 1e6) with impulses lw 1 lc rgb "blue" title "demand (OOCNoPre)", \
     logf("vm", fig9) using "frame":(column("demand_bytes") / 1e6) with impulses lw 1 lc rgb "red" title "vm (OOCPre)"
unset y2tics
unset y2label
set ylabel "MB fetched (10^6 stored bytes)"
set title "(b) summed over the frames so far"
acc = 0
plot logf("demand", fig9) using "frame":(acc = ($0 == 0 ? 0 : acc) + column("demand_bytes") / 1e6) with lines lw 2 lc rgb "blue" title "demand (OOCNoPre)", \
     logf("vm", fig9) using "frame":(acc = ($0 == 0 ? 0 : acc) + column("demand_bytes") / 1e6) with lines lw 2 lc rgb "red" title "vm (OOCPre)"
unset multiplot
