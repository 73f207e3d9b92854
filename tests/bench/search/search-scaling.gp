# Plots the CSV of bench_search:  gnuplot -c tests/bench/search/search-scaling.gp search-scaling.csv \
#                                             docs/img/search-scaling.png
csv = ARGC >= 1 ? ARG1 : 'search-scaling.csv'
png = ARGC >= 2 ? ARG2 : 'search-scaling.png'
set terminal pngcairo size 900,600 font ",11"
set output png
set datafile separator ","
set logscale xy
set format x "10^{%L}"
set format y "10^{%L}"
set xlabel "master faces n (one query box per slave node, about n queries)"
set ylabel "wall time [s]"
set title "Contact broad phase: AABB tree vs brute force (QUAD4 surfaces, 1 core)"
set key top left
set grid
# reference slopes through the tree total at n = 10^4
t4 = 0.006
nlogn(x) = t4 * x * log(x) / (1e4 * log(1e4))
nsq(x) = 0.12 * (x / 1e4)**2
plot "< grep curved ".csv u 2:($4+$6) w lp pt 7 lc rgb "#1f77b4" t "tree: build + n queries (curved)", \
     "< grep flat ".csv u 2:($4+$6) w lp pt 6 lc rgb "#1f77b4" dt 2 t "tree: build + n queries (flat)", \
     "< grep curved ".csv u 2:4 w lp pt 5 lc rgb "#2ca02c" t "tree build (median split)", \
     "< grep curved ".csv u 2:5 w lp pt 4 lc rgb "#9467bd" t "tree refit", \
     "< grep curved ".csv u 2:($9 > 0 ? $9 : 1/0) w lp pt 9 lc rgb "#d62728" t "brute force: n queries (curved)", \
     "< grep flat ".csv u 2:($9 > 0 ? $9 : 1/0) w lp pt 8 lc rgb "#d62728" dt 2 t "brute force (flat)", \
     [1e3:1e6] nlogn(x) w l lc rgb "#555555" lw 2 dt 3 t "∝ n log n", \
     [1e3:1e5] nsq(x) w l lc rgb "black" lw 1 dt 4 t "∝ n^{2}"
