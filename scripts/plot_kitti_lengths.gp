# KITTI errors per sub-sequence length, from socc-eval's kitti_lengths.dat.
# Usage: gnuplot -e "dir='PLOT_DIR'" scripts/plot_kitti_lengths.gp  -> PLOT_DIR/kitti_lengths.png
if (!exists("dir")) dir = "."
set terminal pngcairo size 1000,450 enhanced font "sans,10"
set output dir."/kitti_lengths.png"
set grid
set xlabel "sub-sequence length [m]"
set yrange [0:*]
set multiplot layout 1,2
set title "translational error vs length"
set ylabel "[%]"
plot dir."/kitti_lengths.dat" using 1:3 with linespoints pt 7 lc rgb "#d62728" notitle
set title "rotational error vs length"
set ylabel "[deg/100 m]"
plot dir."/kitti_lengths.dat" using 1:4 with linespoints pt 7 lc rgb "#1f77b4" notitle
unset multiplot
