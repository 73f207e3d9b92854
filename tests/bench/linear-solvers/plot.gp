# Plots docs/linear-solvers.csv (bench_linear_solvers): time against unknowns, one panel per dimension.
#   gnuplot -c tests/bench/linear-solvers/plot.gp [csv [png]]   (defaults: docs/linear-solvers.csv, docs/img/...)
csv = ARGC >= 1 ? ARG1 : 'docs/linear-solvers.csv'
png = ARGC >= 2 ? ARG2 : 'docs/img/linear-solvers.png'
set datafile separator ','
set terminal pngcairo size 1200,520 font ',11'
set output png
set logscale xy
set grid
set key top left
set xlabel 'unknowns'
set ylabel 'wall time [s]'
set format y '10^{%L}'
solvers = 'klu2 klu mumps gmres-muelu gmres-ilu'
colours = '#1b9e77 #66a61e #e7298a #d95f02 #7570b3'
# the rows of all solvers interleave in the CSV: select one series (successful runs only) so lines join it alone
series(dim, solver) = sprintf("< awk -F, '$1 == %d && $4 == \"%s\" && $5 == 1' '%s'", dim, solver, csv)
set multiplot layout 1,2 title 'Linear elasticity, clamped beam, 1 rank: setup + first solve (solid), re-solve on the same pattern (dashed)'
do for [dim = 2:3] {
  set title sprintf('%dD (%s)', dim, dim == 2 ? 'quad4, plane strain' : 'hex8')
  plot for [i = 1:5] series(dim, word(solvers, i)) using 2:($7 + $8) with linespoints lw 2 pt 7 \
         lc rgb word(colours, i) title word(solvers, i), \
       for [i = 1:5] series(dim, word(solvers, i)) using 2:9 with linespoints lw 1 dt 2 pt 6 \
         lc rgb word(colours, i) notitle
}
unset multiplot
