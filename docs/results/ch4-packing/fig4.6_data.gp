# granule: gnuplot body of fig4.6_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set format y '10^{%L}'
set format x '%g'
set key outside right noenhanced
set xlabel 'k' noenhanced
set ylabel 'S(k)' noenhanced
set title "S(k) against the packing fraction, eps_n = 0.4, eps_t = 1 (binned shells)" noenhanced
plot for [i=0:11] 'fig4.6_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i+1 title columnheader(1)

