# granule: gnuplot body of fig5.10-k_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set datafile missing 'nan'
set logscale y
set format y '10^{%L}'
set key below height 1.5 noenhanced
set xlabel '|v| (m/s)'
set ylabel 'P(v) (s/m)'
set title "P(v) of each run (points) and the SPM from its free paths, times k (lines)" noenhanced
plot for [i=0:7] 'fig5.10-k_pv.dat' index i using 1:2 with points pt 7 ps 0.4 lc i+1 title columnheader(1), for [i=0:7] '' index i using 1:4 with lines lw 2 lc i+1 notitle

