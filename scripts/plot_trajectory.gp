# Top view of ground truth vs estimate, from socc-eval's trajectory.dat.
# Usage: gnuplot -e "dir='PLOT_DIR'" scripts/plot_trajectory.gp  -> PLOT_DIR/trajectory.png
# Equal axes; the short axis is padded to at least half the long one so a straight drive does
# not collapse to a flat strip, one round tick step (<= 7 ticks) serves both axes, and the
# canvas follows the data's aspect.
if (!exists("dir")) dir = "."
data = dir."/trajectory.dat"
min(a, b) = a < b ? a : b
max(a, b) = a > b ? a : b
stats data using 2:3 nooutput name "G"
stats data using 4:5 nooutput name "E"
stats data using 6:7 nooutput name "A"
x0 = min(G_min_x, min(E_min_x, A_min_x)); x1 = max(G_max_x, max(E_max_x, A_max_x))
y0 = min(G_min_y, min(E_min_y, A_min_y)); y1 = max(G_max_y, max(E_max_y, A_max_y))
span = max(max(x1 - x0, y1 - y0), 1.0)
half_x = 0.55 * max(x1 - x0, 0.5 * span); half_y = 0.55 * max(y1 - y0, 0.5 * span)
nice(v) = (m = 10**floor(log10(v)), f = v / m, (f <= 1 ? 1 : f <= 2 ? 2 : f <= 5 ? 5 : 10) * m)
tick = nice(2 * max(half_x, half_y) / 6)
height = int(min(1000, max(500, 180 + 820 * half_y / half_x)))
set terminal pngcairo size 1000,height enhanced font "sans,11"
set output dir."/trajectory.png"
set title "Trajectory (top view, equal axes)"
set xlabel "[m]"
set ylabel "[m]"
set size ratio -1
set xrange [(x0 + x1) / 2 - half_x : (x0 + x1) / 2 + half_x]
set yrange [(y0 + y1) / 2 - half_y : (y0 + y1) / 2 + half_y]
set xtics tick
set ytics tick
set format "%g"
set grid
set key outside top center horizontal
plot data using 2:3 with lines lw 2 lc rgb "black" title "ground truth", \
     ""   using 4:5 with lines lw 1.5 lc rgb "#d62728" title "estimate", \
     ""   using 6:7 with lines lw 1 dt 2 lc rgb "#1f77b4" title "estimate (SE3-aligned)", \
     ""   every ::0::0 using 2:3 with points pt 7 ps 1.5 lc rgb "black" title "start"
