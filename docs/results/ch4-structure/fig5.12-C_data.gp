# granule: gnuplot body of fig5.12-C_data.gp (run inside this folder); granule plot DIR redraws it
array T[8] = ["N = 1000, L = 0.2 m", "N = 2000, L = 0.2 m", "N = 3000, L = 0.2 m", "N = 4000, L = 0.4 m", "N = 8000, L = 0.4 m", "N = 12000, L = 0.4 m", "N = 18000, L = 0.6 m", "N = 27000, L = 0.6 m"]
set datafile separator whitespace
set datafile missing 'nan'
set logscale y
set format y '10^{%L}'
set key below height 1.5 noenhanced
set xlabel '|v| (m/s)'
set ylabel 'P(v) (s/m)'
set title "fig5.12-C: the runs' P(v), 5.31 with the predicted S (solid) and fitted (dashed)" noenhanced
plot for [i=0:7] 'fig5.12-C_tail.dat' index i using 1:3 with points pt 7 ps 0.4 lc i+1 title T[i+1], for [i=0:7] '' index i using 1:7 with lines lw 2 lc i+1 notitle, for [i=0:7] '' index i using 1:6 with lines lw 1 dt 2 lc i+1 notitle

