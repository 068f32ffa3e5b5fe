# granule: gnuplot body of fig3.7_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale y
set format y '10^{%L}'
set format x '%g'
set xlabel 'v / <v^2>^(1/2)' noenhanced
set ylabel 'P(v) <v^2>^(1/2)' noenhanced
set key below height 1.5 noenhanced
set multiplot layout 1,1 title "P(v) at eps = 0.99 over N = 251-1585, the speed scaled by <v^2>^(1/2) (Fig. 3.7)" noenhanced font ',13'
plot for [i=0:5] 'fig3.7_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-0+1 title columnheader(1)
unset multiplot

