# Varadhan & Manocha 2002 Fig. 11: bytes the vm loader (OOCPre) fetches on demand per frame as
# the memory footprint grows (factors x the largest front), against half the front's size;
# (b) the same summed from the first frame, vm solid, demand (no prefetching) dashed.
set multiplot layout 2,1 title sprintf("Fig. 11 in kind: demand-fetched bytes by footprint, %s", name)
set xlabel "frame"
set ylabel "MB (10^6 bytes)"
set yrange [0:*]
n = words(factors)
colors = "red blue dark-green orange purple brown"
set title "(a) vm, per frame: fetched (stored bytes, left axis) and half the front (decoded bytes, right axis)"
set ylabel "MB fetched (10^6 stored bytes)"
set y2label "MB (10^6 decoded bytes)"
set y2range [0:*]
set y2tics
plot logf("vm", word(factors, 1)) using "frame":(column("front_bytes") / 2e6) axes x1y2 with lines lw 1 lc rgb "black" title "front / 2 (decoded, right axis)", \
     for [i = 1:n] logf("vm", word(factors, i)) using "frame":(column("demand_bytes") / 1e6) with impulses lw 1 \
       lc rgb word(colors, i) title sprintf("footprint %s x front", word(factors, i))
unset y2tics
unset y2label
set ylabel "MB fetched (10^6 stored bytes)"
set title "(b) summed over the frames so far: vm (solid), demand (dashed)"
acc = 0
plot for [i = 1:n] logf("vm", word(factors, i)) using "frame":(acc = ($0 == 0 ? 0 : acc) + column("demand_bytes") / 1e6) \
       with lines lw 2 lc rgb word(colors, i) title sprintf("vm %s x front", word(factors, i)), \
     for [i = 1:n] logf("demand", word(factors, i)) using "frame":(acc = ($0 == 0 ? 0 : acc) + column("demand_bytes") / 1e6) \
       with lines lw 1 dt 2 lc rgb word(colors, i) title sprintf("demand %s x front", word(factors, i))
unset multiplot
