# Shared settings of the Figure 6.x plots (scripts/plot_figures.sh passes walk, fly, drive,
# levelsWalk, levelsFly, hasFly, hasDrive, budget and out with -e).
set terminal pngcairo size 1280,800 enhanced font "sans,11"
set output out
set datafile columnheaders
set grid
set key outside right top
