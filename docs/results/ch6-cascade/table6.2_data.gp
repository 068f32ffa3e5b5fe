# granule: gnuplot body of table6.2_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set format y '10^{%L}'
set key below height 1.5 noenhanced
set xlabel 'k (1/m)'
set ylabel 'S(k) / S(k_1) x 10^{-i}'
set title "Cascade fields' S(k) (6.5), 256 x 256 over 1 m (Fig. 6.2), fits of table6.2" noenhanced
plot for [i=0:6] 'table6.2_sk.dat' index i using 1:2 with points pt 7 ps 0.5 lc i+1 title columnheader(1), for [i=0:6] '' index i using 1:3 with lines lw 2 lc i+1 notitle

