# granule: gnuplot body of fig3.12.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Power index n_N of the nearest-neighbour distribution G_1(R;N) ~ (-ln R)^(n_N - 1) (3.22)" noenhanced
set ylabel 'n_N' noenhanced
set xtics rotate by 90 right font ',11' noenhanced
set xlabel 'eps_n, N' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig3.12_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule', '' using ($1+0.15):5:6 with yerrorbars pt 6 ps 1.2 lc rgb '#c0392b' title 'thesis'

