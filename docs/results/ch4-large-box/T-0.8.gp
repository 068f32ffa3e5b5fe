# granule: gnuplot body of T-0.8.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Steady granular temperature (2.19), both components, at L = 0.8 m" noenhanced
set ylabel 'T / m^2/s^2' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'N, eps_n, eps_t' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'T-0.8_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule'

