# granule: gnuplot body of fig5.14a_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale y
set format y '10^{%L}'
set format x '%g'
set xlabel 'v (m/s)' noenhanced
set ylabel 'P(v)' noenhanced
set key below height 1.5 noenhanced
set multiplot layout 1,1 title "P(v) and its crossover fit P_0(v) (5.32), L = 0.4 m, eps_t = 0.1" noenhanced font ',13'
plot for [i=0:3] 'fig5.14a_blocks.dat' index i using 1:2 with points pt 7 ps 0.5 lc i-0+1 title columnheader(1), for [i=0:3] 'fig5.14a_overlay.dat' index i using 1:2 with lines dt 2 lw 2 lc i-0+1 title (i == 0 ? 'P_0(v) (5.32) fitted on log axes (dashed)' : '')
unset multiplot

