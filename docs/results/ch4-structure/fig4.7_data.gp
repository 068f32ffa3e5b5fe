# granule: gnuplot body of fig4.7_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set format y '10^{%L}'
set format x '%g'
set xlabel 'R / d' noenhanced
set ylabel 'g' noenhanced
set key below height 1.5 noenhanced
set multiplot layout 1,1 title "Pair correlation g(R) (4.10), eps_n = eps_t = 0.1" noenhanced font ',13'
plot for [i=0:7] 'fig4.7_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-0+1 title columnheader(1)
unset multiplot

