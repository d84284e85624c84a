# Errors over frames, from socc-eval's errors.dat.
# Usage: gnuplot -e "dir='PLOT_DIR'" scripts/plot_errors.gp  -> PLOT_DIR/errors.png
if (!exists("dir")) dir = "."
set terminal pngcairo size 1000,900 enhanced font "sans,10"
set output dir."/errors.png"
set datafile missing "NaN"
set grid
set xlabel "frame"
set multiplot layout 3,1
set title "ATE after SE(3) alignment"
set ylabel "[m]"
plot dir."/errors.dat" using 1:2 with lines lc rgb "#1f77b4" notitle
set title "RPE translation (delta = 1 frame)"
set ylabel "[m]"
plot dir."/errors.dat" using 1:3 with lines lc rgb "#d62728" notitle
set title "RPE rotation (delta = 1 frame)"
set ylabel "[deg]"
plot dir."/errors.dat" using 1:4 with lines lc rgb "#2ca02c" notitle
unset multiplot
