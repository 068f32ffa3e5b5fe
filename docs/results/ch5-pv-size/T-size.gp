# granule: gnuplot body of T-size.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Steady granular temperature (2.19) over the box size" noenhanced
set ylabel 'T / m^2/s^2' noenhanced
set xlabel 'N' noenhanced
set logscale x
set key below height 1.5
set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot for [i=0:6] 'T-size_compare.dat' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title columnheader(1)

