# granule: gnuplot body of fig5.11-coefficient.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "The same tail in s^2/m^2: Q ~ exp(-c v^2) with c = b (M^2 / 2 D l)^(2/3)" noenhanced
set ylabel 'c / s^2/m^2' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'l' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig5.11-coefficient_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule', '' using ($1+0.15):5:6 with yerrorbars pt 6 ps 1.2 lc rgb '#c0392b' title 'thesis'

