# Top view of ground truth vs estimate, from socc-eval's trajectory.dat.
# Usage: gnuplot -e "dir='PLOT_DIR'" scripts/plot_trajectory.gp  -> PLOT_DIR/trajectory.png
if (!exists("dir")) dir = "."
set terminal pngcairo size 900,800 enhanced font "sans,10"
set output dir."/trajectory.png"
set title "Trajectory (top view)"
set xlabel "[m]"
set ylabel "[m]"
set size ratio -1
set grid
set key outside bottom center horizontal
plot dir."/trajectory.dat" using 2:3 with lines lw 2 lc rgb "black" title "ground truth", \
     ""                    using 4:5 with lines lw 1.5 lc rgb "#d62728" title "estimate", \
     ""                    using 6:7 with lines lw 1 dt 2 lc rgb "#1f77b4" title "estimate (SE3-aligned)", \
     ""                    every ::0::0 using 2:3 with points pt 7 ps 1.5 lc rgb "black" title "start"
