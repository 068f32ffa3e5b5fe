# granule: gnuplot body of fig5.2.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Moments of the speed against N at L = 0.2 m (phi = N pi r^2 / L^2): xi_m / m of <|v|^m> ~ N^-xi_m, phi < 0.1" noenhanced
set ylabel 'xi_m/m' noenhanced
set xlabel 'm' noenhanced
set key below height 1.5
set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot for [i=0:0] 'fig5.2_compare.dat' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title columnheader(1), for [i=0:0] '' index i using 1:4:5 with yerrorbars pt 6 ps 2 lc i+1 notitle, NaN with points pt 6 ps 2 lc rgb 'black' title 'thesis (open)'

