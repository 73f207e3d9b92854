# mortar-dual scaling study: CPU seconds per Newton iteration against dofs, log-log, for Hertz 3D and the 3D
# ironing (saddle-point / condensed x MUMPS / GMRES + MueLu). Data: tests/bench/mortar-dual/scaling.py (run it
# first; it writes results/bench/mortar-scaling/*.dat). Run from the repository's root:
#   gnuplot tests/bench/mortar-dual/scaling.gp     -> docs/img/mortar-dual-scaling.png
dir = 'results/bench/mortar-scaling/'
set terminal pngcairo size 1200,520 font ',10'
set output 'docs/img/mortar-dual-scaling.png'
set multiplot layout 1,2
set logscale xy
set grid
set xlabel 'dofs'
set ylabel 'CPU s per Newton iteration'
set key top left
f(study, strategy, solver) = sprintf('%s%s-%s-%s.dat', dir, study, strategy, solver)
do for [study in 'hertz-3d ironing-3d'] {
  set title study
  plot f(study, 'saddle-point', 'direct') u 1:2 w lp pt 5 lc rgb '#1f77b4' t 'saddle-point, MUMPS', \
       f(study, 'condensed', 'direct') u 1:2 w lp pt 7 lc rgb '#ff7f0e' t 'condensed, MUMPS', \
       f(study, 'saddle-point', 'gmres-muelu') u 1:2 w lp pt 4 dt 2 lc rgb '#2ca02c' t 'saddle-point, GMRES + MueLu', \
       f(study, 'condensed', 'gmres-muelu') u 1:2 w lp pt 6 dt 2 lc rgb '#d62728' t 'condensed, GMRES + MueLu', \
       [x=1000:100000] 1e-5 * x w l dt 3 lc rgb 'gray' t 'O(n)'
}
unset multiplot
