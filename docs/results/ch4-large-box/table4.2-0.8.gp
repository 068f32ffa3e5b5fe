# granule: gnuplot body of table4.2-0.8.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Fractal dimension D_f of S(k) at L = 0.8 m, phi = 0.530, eps_t = 1 over eps_n (Table 4.2's column)" noenhanced
set ylabel 'D_f' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'N, eps_n, eps_t' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'table4.2-0.8_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule', '' using ($1+0.15):5:6 with yerrorbars pt 6 ps 1.2 lc rgb '#c0392b' title 'thesis'

