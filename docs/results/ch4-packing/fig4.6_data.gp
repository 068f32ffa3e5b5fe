# granule: gnuplot body of fig4.6_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set format y '10^{%L}'
set format x '%g'
set xlabel 'k' noenhanced
set ylabel 'S(k)' noenhanced
set key top right font ',9' noenhanced
set tics font ',10'
set title font ',12'
set xlabel font ',11'
set ylabel font ',11'
set multiplot layout 4,3 title "S(k) against the packing fraction, eps_n = 0.4, eps_t = 1 (binned shells)" noenhanced font ',13'
plot for [i=0:0] 'fig4.6_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-0+1 title columnheader(1)
unset key
set key top right font ',9' noenhanced
plot for [i=1:1] 'fig4.6_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-1+1 title columnheader(1)
plot for [i=2:2] 'fig4.6_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-2+1 title columnheader(1)
plot for [i=3:3] 'fig4.6_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-3+1 title columnheader(1)
plot for [i=4:4] 'fig4.6_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-4+1 title columnheader(1)
plot for [i=5:5] 'fig4.6_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-5+1 title columnheader(1)
plot for [i=6:6] 'fig4.6_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-6+1 title columnheader(1)
plot for [i=7:7] 'fig4.6_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-7+1 title columnheader(1)
plot for [i=8:8] 'fig4.6_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-8+1 title columnheader(1)
plot for [i=9:9] 'fig4.6_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-9+1 title columnheader(1)
plot for [i=10:10] 'fig4.6_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-10+1 title columnheader(1)
plot for [i=11:11] 'fig4.6_blocks.dat' index i using 1:2 with linespoints pt 7 ps 0.5 lc i-11+1 title columnheader(1)
unset multiplot

