# Plots docs/linear-solvers-contact.csv (contact-systems.sh): CPU time per solve and GMRES iterations against
# unknowns for the two-tori contact systems at refine 0.25 .. 1.
#   gnuplot -c tests/bench/linear-solvers/contact-systems.gp [csv [png]]
csv = ARGC >= 1 ? ARG1 : 'docs/linear-solvers-contact.csv'
png = ARGC >= 2 ? ARG2 : 'docs/img/linear-solvers-contact.png'
set datafile separator ','
set terminal pngcairo size 1200,520 font ',11'
set output png
set grid
set key top left
set xlabel 'unknowns'
solvers = 'mumps gmres-muelu gmres-sgs gmres-ilu'
colours = '#e7298a #d95f02 #1b9e77 #7570b3'
# first of the two systems per size (solve 26), successful runs only
series(solver) = sprintf("< awk -F, 'NR > 1 && $5 == \"%s\" && $13 == 0 && $2 == 26' '%s'", solver, csv)
set multiplot layout 1,2 title 'Two-tori contact systems (nts-augmented, reduced), t = 0.1, 1 rank'
set title 'CPU time: set-up + solve (solid), re-solve with the kept set-up (dashed)'
set logscale xy
set ylabel 'CPU seconds'
set format y '10^{%L}'
plot for [i = 1:4] series(word(solvers, i)) using 3:8 with linespoints lw 2 pt 7 lc rgb word(colours, i) \
       title word(solvers, i), \
     for [i = 1:4] series(word(solvers, i)) using 3:10 with linespoints lw 1 dt 2 pt 6 lc rgb word(colours, i) notitle
set title 'GMRES iterations to 1e-10 (bounded under refinement)'
unset logscale y
set logscale x
set format y '%g'
set ylabel 'iterations'
set yrange [0:*]
plot for [i = 2:4] series(word(solvers, i)) using 3:7 with linespoints lw 2 pt 7 lc rgb word(colours, i) \
       title word(solvers, i)
unset multiplot
