# granule: gnuplot body of fig4.6_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set format y '10^{%L}'
set format x '%g'
set xlabel 'k (1/m)' noenhanced
set ylabel 'S(k)' noenhanced
set key top right font ',9' noenhanced
set tics font ',10'
set title font ',12'
set xlabel font ',11'
set ylabel font ',11'
set multiplot layout 1,2 title "S(k) against the packing fraction, eps_n = 0.4, eps_t = 1 (binned shells)" noenhanced font ',13'
plot for [i=0:5] 'fig4.6_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-0+1 title columnheader(1)
unset key
set key top right font ',9' noenhanced
plot for [i=6:11] 'fig4.6_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-6+1 title columnheader(1)
unset multiplot

