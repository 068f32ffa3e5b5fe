# granule: gnuplot body of fig4.5_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set format y '10^{%L}'
set format x '%g'
set xlabel 'k d' noenhanced
set ylabel 'S(k)' noenhanced
set key below height 1.5 noenhanced
set multiplot layout 1,1 title "S(k), L = 0.4 m, eps_n = 0.9 (Case III)" noenhanced font ',13'
plot for [i=0:4] 'fig4.5_blocks.dat' index i using 1:2 with points pt 7 ps 0.5 lc i-0+1 title columnheader(1), for [i=0:4] 'fig4.5_overlay.dat' index i using 1:2 with lines dt 2 lw 2 lc i-0+1 title (i == 0 ? 'A k^-1.63, the thesis''s form (dashed)' : '')
unset multiplot

