# granule: gnuplot body of fig2.7-settle.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Time after which T(t) stays at its steady value (100 ms means within 3 sd of the steady state's)" noenhanced
set ylabel 't_settle / s' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'eps_n, kind' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig2.7-settle_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule', '' using ($1+0.15):5:6 with yerrorbars pt 6 ps 1.2 lc rgb '#c0392b' title 'thesis'

