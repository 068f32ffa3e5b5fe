# granule: gnuplot body of fig5.3_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale y
set format y '10^{%L}'
set format x '%g'
set xlabel 'v (m/s)' noenhanced
set ylabel 'P(v) / P(1 m/s)' noenhanced
set key top right font ',9' noenhanced
set tics font ',10'
set title font ',12'
set xlabel font ',11'
set ylabel font ',11'
set multiplot layout 1,2 title "P(v) scaled to agree at v = 1 m/s (5.4), L = 0.2 m, N = 3000, eps_n = eps_t" noenhanced font ',13'
plot for [i=0:4] 'fig5.3_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-0+1 title columnheader(1)
unset key
set key top right font ',9' noenhanced
plot for [i=5:9] 'fig5.3_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-5+1 title columnheader(1)
unset multiplot

