# granule: gnuplot body of fig3.17_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set format y '10^{%L}'
set format x '%g'
set xlabel '-ln R' noenhanced
set ylabel 'A_N G^{1/(n-1)}  (3.39)' noenhanced
set key inside top left noenhanced
set multiplot layout 1,1 title "Collapse of G_1(R;N) by the bisection map (3.39-3.40), eps = 0.1" noenhanced font ',13'
plot for [i=0:7] 'fig3.17_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-0+1 title columnheader(1), x with lines dt 2 lw 2 lc rgb 'black' title 'uniform bisection (3.36): -ln R'
unset multiplot

