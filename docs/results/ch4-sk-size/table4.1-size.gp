# granule: gnuplot body of table4.1-size.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Fractal dimension D_f of S(k) = A k^-D_f (4.4) below k', over the box size" noenhanced
set ylabel 'D_f' noenhanced
set xlabel 'L (m)' noenhanced
set key below height 1.5
set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot for [i=0:6] 'table4.1-size_compare.dat' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title columnheader(1), for [i=0:6] '' index i using 1:4:5 with yerrorbars pt 6 ps 2 lc i+1 notitle, NaN with points pt 6 ps 2 lc rgb 'black' title 'thesis (open)'

