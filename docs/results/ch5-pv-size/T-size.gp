# granule: gnuplot body of T-size.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Steady granular temperature (2.19) over the box size" noenhanced
set ylabel 'T / m^2/s^2' noenhanced
set xtics rotate by 90 right font ',11' noenhanced
set xlabel 'N, L (m)' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'T-size_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule'

