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
set key autotitle columnhead outside right
set multiplot layout 2,2 title "$title"
set xlabel "time"
set title "energy"
plot "$csv" using "time":"kinetic_energy" with lines lw 2, \
     "" using "time":"strain_energy" with lines lw 2, \
     "" using "time":"total_energy" with lines lw 2
set title "linear momentum"
plot "$csv" using "time":"momentum_x" with lines lw 2, "" using "time":"momentum_y" with lines lw 2, \
     "" using "time":"momentum_z" with lines lw 2
set title "angular momentum (about the origin)"
plot "$csv" using "time":"angular_momentum_x" with lines lw 2, "" using "time":"angular_momentum_y" with lines lw 2, \
     "" using "time":"angular_momentum_z" with lines lw 2
set title "contact force and active points"
set y2tics
plot "$csv" using "time":"contact_force_x" with lines lw 2, "" using "time":"contact_force_y" with lines lw 2, \
     "" using "time":"contact_force_z" with lines lw 2, "" using "time":"active_points" axes x1y2 with steps
unset multiplot
GP
echo "plot: $dir/history.png"
