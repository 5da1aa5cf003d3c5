# Thesis Fig. 6.1 (§6.1, memory management, §4.3): memory used over time. Real bytes held
# (uploaded + decoded + loading) and the c_memory * cost estimate that the loader bounds.
set title "Figure 6.1: memory over time (§4.3)"
set xlabel "time (s)"
set ylabel "memory (MiB)"
set yrange [0:*]
plot run1 using "time_s":"resident_mib" with lines lw 2 title "resident bytes", \
     run1 using "time_s":"estimate_mib" with lines lw 1 dt 2 title "c_{memory} x cost"
