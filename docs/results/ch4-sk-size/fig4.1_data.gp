# granule: gnuplot body of fig4.1_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set format y '10^{%L}'
set format x '%g'
set xlabel 'k d' noenhanced
set ylabel 'S(k)' noenhanced
set key below height 1.5 noenhanced
set multiplot layout 1,1 title "S(k) at phi = 0.088 as the box grows, L = 0.2-1.2 m (Fig. 4.1)" noenhanced font ',13'
plot for [i=0:5] 'fig4.1_blocks.dat' index i using 1:2 with points pt 7 ps 0.5 lc i-0+1 title columnheader(1), for [i=0:5] 'fig4.1_overlay.dat' index i using 1:2 with lines dt 2 lw 2 lc i-0+1 title (i == 0 ? 'A k^-1.63, the thesis''s large-box form (dashed)' : '')
unset multiplot

