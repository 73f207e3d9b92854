# Plots the CSV of broad_phase.py:  gnuplot -c tests/bench/many-bodies/broad-phase.gp broad-phase.csv broad-phase.png
csv = ARGC >= 1 ? ARG1 : 'broad-phase.csv'
png = ARGC >= 2 ? ARG2 : 'broad-phase.png'
set terminal pngcairo size 1100,480 font ",11"
set output png
set datafile separator ","
set multiplot layout 1,2 title "Broad phase over the pairs created by bodies: all (N disks in a box, penalty-nts, midpoint)"
set logscale xy
set xlabel "bodies N"
set ylabel "wall seconds"
set format y "10^{%L}"
set key bottom right font ",9"
set grid
# reference slopes through the first point
stats csv u 1:7 every ::1::1 nooutput
n0 = STATS_min_x
b0 = STATS_min_y
plot csv u 1:7 every ::1 w lp pt 7 lc rgb "#1f77b4" t "broad phase per step", \
     csv u 1:10 every ::1 w lp pt 6 lc rgb "#1f77b4" dt 2 t "broad phase per sweep", \
     csv u 1:($13/$3) every ::1 w lp pt 5 lc rgb "#2ca02c" t "contact, with the broad phase", \
     csv u 1:($14/$3) every ::1 w lp pt 4 lc rgb "#d62728" t "contact, without (every pair calls its plugin)", \
     [2:128] b0 * x * log(x) / (n0 * log(n0)) w l lc rgb "#555555" dt 3 lw 2 t "∝ N log N", \
     [2:128] b0 * (x / n0)**2 w l lc rgb "black" dt 4 t "∝ N^{2}"
set ylabel "share of the run's wall time [%]"
set yrange [1e-3:10]
set key top left font ",9"
plot csv u 1:(100*$8) every ::1 w lp pt 7 lc rgb "#1f77b4" t "broad phase / wall", \
     5 w l lc rgb "#d62728" dt 2 t "5 %"
unset multiplot
