# granule: gnuplot body of fig3.16_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set format y '10^{%L}'
set format x '%g'
set xlabel 'R' noenhanced
set ylabel 'G_1' noenhanced
set key below height 1.5 noenhanced
set multiplot layout 1,1 title "G_1(R), N = 512, beside the uniform bisection process, n = 9 (3.36)" noenhanced font ',13'
plot for [i=0:1] 'fig3.16_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-0+1 title columnheader(1)
unset multiplot

