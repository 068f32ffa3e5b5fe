# granule: gnuplot body of figA.1_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale y
set format y '10^{%L}'
set format x '%g'
set xlabel 'v (m/s)' noenhanced
set ylabel 'P(v)' noenhanced
set key below height 1.5 noenhanced
set multiplot layout 1,1 title "P(v) at N = 1000 for eps = 0.1-0.99 (Fig. A.1)" noenhanced font ',13'
plot for [i=0:5] 'figA.1_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-0+1 title columnheader(1)
unset multiplot

