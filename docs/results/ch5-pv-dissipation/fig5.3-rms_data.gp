# granule: gnuplot body of fig5.3-rms_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale y
set format y '10^{%L}'
set format x '%g'
set xlabel 'v / v_rms' noenhanced
set ylabel 'P(v) / P(v_rms)' noenhanced
set key top right font ',9' noenhanced
set tics font ',10'
set title font ',12'
set xlabel font ',11'
set ylabel font ',11'
set multiplot layout 1,2 title "The same P(v) against v / v_rms, scaled to 1 at v = v_rms" noenhanced font ',13'
plot for [i=0:4] 'fig5.3-rms_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-0+1 title columnheader(1)
unset key
set key top right font ',9' noenhanced
plot for [i=5:9] 'fig5.3-rms_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-5+1 title columnheader(1)
unset multiplot

