#!/usr/bin/env bash
# Plots a run's energy, momentum and contact-force histories (history.csv) into DIR/history.png with gnuplot.
# Usage: scripts/plot-history.sh RESULTS_DIR [title]
set -euo pipefail
dir=${1:?usage: plot-history.sh RESULTS_DIR [title]}
title=${2:-$(basename "$dir")}
csv="$dir/history.csv"
[ -f "$csv" ] || { echo "plot-history: no $csv" >&2; exit 1; }
command -v gnuplot >/dev/null || { echo "plot-history: gnuplot is not installed (scripts/install-deps.sh)" >&2; exit 1; }
gnuplot <<GP
set datafile separator ","
set terminal pngcairo size 1400,900 noenhanced font ",10"
set output "$dir/history.png"
set key top right box opaque
set multiplot layout 2,2 title "$title"
set xlabel "time"
# initial values (first data row) for the relative changes
stats "$csv" using "total_energy" every ::0::0 nooutput
E0 = STATS_min
stats "$csv" using (sqrt(column("angular_momentum_x")**2 + column("angular_momentum_y")**2 + column("angular_momentum_z")**2)) every ::0::0 nooutput
L0 = STATS_min > 0 ? STATS_min : 1
stats "$csv" using "angular_momentum_x" every ::0::0 nooutput
Lx0 = STATS_min
stats "$csv" using "angular_momentum_y" every ::0::0 nooutput
Ly0 = STATS_min
stats "$csv" using "angular_momentum_z" every ::0::0 nooutput
Lz0 = STATS_min
set title "energy"
plot "$csv" using "time":"kinetic_energy" with lines lw 2 title "kinetic", \
     "" using "time":"strain_energy" with lines lw 2 title "strain", \
     "" using "time":"total_energy" with lines lw 2 title "total"
set title "conservation: relative change since t0"
set format y "%.1e"
plot "$csv" using "time":((column("total_energy") - E0) / (E0 != 0 ? abs(E0) : 1)) with lines lw 2 title "(E - E0)/|E0|", \
     "" using "time":((column("angular_momentum_x") - Lx0) / L0) with lines lw 2 title "(Lx - Lx0)/|L0|", \
     "" using "time":((column("angular_momentum_y") - Ly0) / L0) with lines lw 2 title "(Ly - Ly0)/|L0|", \
     "" using "time":((column("angular_momentum_z") - Lz0) / L0) with lines lw 2 title "(Lz - Lz0)/|L0|"
set format y "% g"
set title "linear momentum"
plot "$csv" using "time":"momentum_x" with lines lw 2 title "px", "" using "time":"momentum_y" with lines lw 2 title "py", \
     "" using "time":"momentum_z" with lines lw 2 title "pz"
set title "contact force on the slave side, active points"
set y2tics
set ytics nomirror
plot "$csv" using "time":"contact_force_x" with lines lw 2 title "Fx", "" using "time":"contact_force_y" with lines lw 2 title "Fy", \
     "" using "time":"contact_force_z" with lines lw 2 title "Fz", "" using "time":"active_points" axes x1y2 with steps title "active (right axis)"
unset multiplot
GP
echo "plot: $dir/history.png"
