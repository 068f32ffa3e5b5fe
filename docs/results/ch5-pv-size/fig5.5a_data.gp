# granule: gnuplot body of fig5.5a_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale y
set format y '10^{%L}'
set format x '%g'
set xlabel 'v / v_rms' noenhanced
set ylabel 'P(v) / P(v_rms)' noenhanced
set key below height 1.5 noenhanced
set multiplot layout 1,1 title "P(v) against v / v_rms at phi = 0.088 as the box grows, scaled to 1 at v = v_rms (Fig. 5.5a)" noenhanced font ',13'
plot for [i=0:6] 'fig5.5a_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-0+1 title columnheader(1)
unset multiplot

