# granule: gnuplot body of fig3.2.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Exponent xi_2 of <v^2> = lambda N^-xi_2 (3.8) against eps" noenhanced
set ylabel 'xi_2' noenhanced
set xlabel 'eps_n' noenhanced
set logscale x
set key below height 1.5
set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot for [i=0:0] 'fig3.2_compare.dat' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title columnheader(1), for [i=0:0] '' index i using 1:4:5 with yerrorbars pt 6 ps 2 lc i+1 notitle, NaN with points pt 6 ps 2 lc rgb 'black' title 'thesis (open)'

