# KITTI errors per speed (the devkit's 2 m/s bins), from socc-eval's kitti_speeds.dat.
# Usage: gnuplot -e "dir='PLOT_DIR'" scripts/plot_kitti_speeds.gp  -> PLOT_DIR/kitti_speeds.png
if (!exists("dir")) dir = "."
set terminal pngcairo size 1000,450 enhanced font "sans,10"
set output dir."/kitti_speeds.png"
set grid
set xlabel "speed [m/s] (segment length / duration at 0.1 s per frame)"
set xrange [0:26]
set yrange [0:*]
set multiplot layout 1,2
set title "translational error vs speed"
set ylabel "[%]"
plot dir."/kitti_speeds.dat" using 1:3 with linespoints pt 7 lc rgb "#d62728" notitle
set title "rotational error vs speed"
set ylabel "[deg/100 m]"
plot dir."/kitti_speeds.dat" using 1:4 with linespoints pt 7 lc rgb "#1f77b4" notitle
unset multiplot
