# granule: gnuplot body of df-seeds.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "D_f of S(k) at L = 0.4 m, eps_n = 0.9, from seeds 2-5 (Figs. 4.4-4.5)" noenhanced
set ylabel 'D_f' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'eps_n, eps_t' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'df-seeds_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule', '' using ($1+0.15):5:6 with yerrorbars pt 6 ps 1.2 lc rgb '#c0392b' title 'thesis'

