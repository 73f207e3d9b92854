# mortar-dual's 3D ironing reactions. Data: python3 tests/bench/mortar-dual/plots.py --ironing-3d (about 100 CPU min).
# Run from the repository's root:  gnuplot tests/bench/mortar-dual/ironing-3d.gp
dir = 'results/bench/mortar-plots/'
set terminal pngcairo size 800,520 font ',10'
set grid
set output 'docs/img/mortar-dual-ironing-3d.png'
set title '3D shallow ironing (half cylinder on a block, frictionless), mortar-dual: reactions at the indenter top'
set xlabel 't  (pressed over [0, 1], moved 10 along x over [1, 2])'
set ylabel '|reaction|'
set key top left
set autoscale
plot for [r in '0.5 0.75 1'] dir.'ironing-3d-refine'.r.'.dat' u 1:(abs($3)) w l lw 1.5 t '|F_z| (press), refine '.r, \
     for [r in '0.5 0.75 1'] dir.'ironing-3d-refine'.r.'.dat' u 1:(abs($2)) w l dt 2 lw 1.5 t '|F_x| (drag), refine '.r
