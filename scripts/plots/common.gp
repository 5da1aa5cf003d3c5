# Shared settings of the Figure 6.x plots (scripts/plot_figures.sh passes run1, run2,
# levels1, levels2, second and out with -e).
set terminal pngcairo size 1280,800 enhanced font "sans,11"
set output out
set datafile columnheaders
set grid
set key outside right top
runName(r) = r == 1 ? "run 1" : (second ? "run 2" : "run 1")
