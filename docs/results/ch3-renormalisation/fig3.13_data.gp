# granule: gnuplot body of fig3.13_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set format y '10^{%L}'
set format x '%g'
set xlabel 'R' noenhanced
set ylabel 'G_h' noenhanced
set key below height 1.5 noenhanced
set multiplot layout 1,1 title "Renormalisation (3.25): G_h(R; N) with h = N/512 against G_1(R; 512)" noenhanced font ',13'
plot for [i=0:3] 'fig3.13_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-0+1 title columnheader(1)
unset multiplot

