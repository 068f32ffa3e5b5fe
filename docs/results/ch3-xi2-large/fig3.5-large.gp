# granule: gnuplot body of fig3.5-large.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Multi-scaling of the velocity moments xi_m / m (3.13) at eps = 0.1 over the window of Fig. 3.5, N = 398-3981" noenhanced
set ylabel 'xi_m/m' noenhanced
set xtics rotate by 90 right font ',11' noenhanced
set xlabel 'eps_n' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig3.5-large_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule', '' using ($1+0.15):5:6 with yerrorbars pt 6 ps 1.2 lc rgb '#c0392b' title 'thesis'

