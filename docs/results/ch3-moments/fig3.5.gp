# granule: gnuplot body of fig3.5.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Multi-scaling of the velocity moments: xi_m / m against m (3.13)" noenhanced
set ylabel 'xi_m/m' noenhanced
set xlabel 'm' noenhanced
set key below height 1.5
set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot for [i=0:6] 'fig3.5_compare.dat' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title columnheader(1), for [i=0:6] '' index i using 1:4:5 with yerrorbars pt 6 ps 2 lc i+1 notitle, NaN with points pt 6 ps 2 lc rgb 'black' title 'thesis (open)'

