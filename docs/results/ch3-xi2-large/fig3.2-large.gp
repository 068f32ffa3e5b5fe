# granule: gnuplot body of fig3.2-large.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Exponent xi_2 of <v^2> = lambda N^-xi_2 (3.8) at eps = 0.1 over the thesis's window, N = 398-10000" noenhanced
set ylabel 'xi_2' noenhanced
set xtics rotate by 90 right font ',11' noenhanced
set xlabel 'eps_n' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig3.2-large_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule', '' using ($1+0.15):5:6 with yerrorbars pt 6 ps 1.2 lc rgb '#c0392b' title 'thesis'

