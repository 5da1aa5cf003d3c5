# Shared settings of the Varadhan & Manocha 2002 Fig. 9-11 plots (scripts/loader_figures.sh
# passes dir, name, fig9, factors, incore and out with -e). Inputs: `hlod play` CSV logs.
set terminal pngcairo size 1280,720 enhanced font "sans,11"
set output out
set datafile separator ","
set datafile columnheaders
set grid
set key outside right top
logf(loader, k) = sprintf("%s/%s-%s-x%s.csv", dir, name, loader, k)
