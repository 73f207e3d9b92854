# mortar-dual's plotted checks. Data: tests/bench/mortar-dual/plots.py (run it first; results/bench/mortar-plots/).
# Run from the repository's root:  gnuplot tests/bench/mortar-dual/plots.gp
dir = 'results/bench/mortar-plots/'
set terminal pngcairo size 800,520 font ',10'
set grid

set output 'docs/img/mortar-dual-hertz-2d.png'
set title "Hertz 2D (Hammer's parameters), mortar-dual: nominal pressure at the slave nodes"
set xlabel 'reference x / b'
set ylabel 'p / p0'
set key top right
set xrange [0:1.5]
set yrange [-0.05:1.1]
plot dir.'hertz-2d-refine1.dat' u 1:3 w l lc rgb 'black' t 'Hertz, p0 sqrt(1 - x^2/b^2)', \
     dir.'hertz-2d-refine1.dat' u 1:2 w p pt 7 lc rgb '#1f77b4' t 'refine 1 (h = 0.05 mm at the contact)', \
     dir.'hertz-2d-refine2.dat' u 1:2 w p pt 6 lc rgb '#d62728' t 'refine 2'

set output 'docs/img/mortar-dual-ironing-2d.png'
set title '2D ironing (Yang, Laursen and Meng; mu = 0.5), mortar-dual: reactions at the die top'
set xlabel 't'
set ylabel '|reaction|'
set key top left
set autoscale
plot for [r in '1 2'] dir.'ironing-2d-refine'.r.'.dat' u 1:(abs($3)) w l lw 1.5 t '|F_y| (press), refine '.r, \
     for [r in '1 2'] dir.'ironing-2d-refine'.r.'.dat' u 1:(abs($2)) w l dt 2 lw 1.5 t '|F_x| (drag), refine '.r
