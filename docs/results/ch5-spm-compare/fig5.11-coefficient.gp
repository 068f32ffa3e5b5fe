# granule: gnuplot body of fig5.11-coefficient.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "The same tail in s^2/m^2: Q ~ exp(-c v^2) with c = b (M^2 / 2 D l)^(2/3)" noenhanced
set ylabel 'c / s^2/m^2' noenhanced
set xlabel 'l' noenhanced
set key below height 1.5
set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot for [i=0:0] 'fig5.11-coefficient_compare.dat' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title columnheader(1), for [i=0:0] '' index i using 1:4:5 with yerrorbars pt 6 ps 2 lc i+1 notitle, NaN with points pt 6 ps 2 lc rgb 'black' title 'thesis (open)'

