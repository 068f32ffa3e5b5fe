# granule: gnuplot body of table5.3-vr.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Gaussian width v_r of the crossover fit P_0(v) (5.32)" noenhanced
set ylabel 'v_r / m/s' noenhanced
set xtics rotate by 90 right font ',11' noenhanced
set xlabel 'eps_n, eps_t' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'table5.3-vr_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule', '' using ($1+0.15):5:6 with yerrorbars pt 6 ps 1.2 lc rgb '#c0392b' title 'thesis'

