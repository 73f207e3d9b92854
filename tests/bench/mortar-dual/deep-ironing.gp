# Hammer's deep ironing (2012, 8.2) with mortar-dual: the reactions at the block's top. Data: python3
# tests/bench/mortar-dual/thesis.py --deep-ironing (hours). Run from the repository's root:
#   gnuplot tests/bench/mortar-dual/deep-ironing.gp   -> docs/img/mortar-dual-deep-ironing.png
dir = 'results/bench/mortar-thesis/'
set terminal pngcairo size 900,900 font ',10'
set grid
set output 'docs/img/mortar-dual-deep-ironing.png'
set multiplot layout 2,1 title "Deep ironing (Hammer 8.2), mortar-dual, concentrated integration: block-top reactions"
set xlabel 't  (pressed 30 mm over [0, 1]; 220 mm right to t = 8.33, 110 mm back to t = 12)'
set ylabel '-F_y (press) [N]'
set key bottom right
plot dir.'deep-M-mu0.dat' u 1:(-$3) w l lw 2 lc rgb '#d62728' t 'mu = 0, normal M', \
     dir.'deep-A-mu0.dat' u 1:(-$3) w l lw 1 lc rgb '#2ca02c' t 'mu = 0, normal A', \
     dir.'deep-M-mu0.3.dat' u 1:(-$3) w l lw 1.5 lc rgb '#1f77b4' t 'mu = 0.3, M, refine 1', \
     dir.'deep-M-mu0.3-refine1.5.dat' u 1:(-$3) w l lw 1 lc rgb '#9467bd' t 'mu = 0.3, M, refine 1.5'
set ylabel 'F_x (iron) [N]'
set key top right
plot dir.'deep-M-mu0.dat' u 1:2 w l lw 2 lc rgb '#d62728' t 'mu = 0, normal M', \
     dir.'deep-A-mu0.dat' u 1:2 w l lw 1 lc rgb '#2ca02c' t 'mu = 0, normal A', \
     dir.'deep-M-mu0.3.dat' u 1:2 w l lw 1.5 lc rgb '#1f77b4' t 'mu = 0.3, M, refine 1', \
     dir.'deep-M-mu0.3-refine1.5.dat' u 1:2 w l lw 1 lc rgb '#9467bd' t 'mu = 0.3, M, refine 1.5'
unset multiplot
