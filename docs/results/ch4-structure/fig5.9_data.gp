# granule: gnuplot body of fig5.9_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale y
set format y '10^{%L}'
set format x '%g'
set xlabel 'v (m/s)' noenhanced
set ylabel 'P_post(v)' noenhanced
set key below height 1.5 noenhanced
set multiplot layout 1,1 title "Post-collision velocity distribution against the whole P(v) (sec. 5.3), eps_n = eps_t = 0.1" noenhanced font ',13'
plot for [i=0:7] 'fig5.9_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-0+1 title columnheader(1)
unset multiplot

