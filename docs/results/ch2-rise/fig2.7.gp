# granule: gnuplot body of fig2.7.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Time for T(t) to reach 90 % of its steady value (50 ms window)" noenhanced
set ylabel 't_rise / s' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'eps_n, kind' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig2.7_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule', '' using ($1+0.15):5:6 with yerrorbars pt 6 ps 1.2 lc rgb '#c0392b' title 'thesis'

