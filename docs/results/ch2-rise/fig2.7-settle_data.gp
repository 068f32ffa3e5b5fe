# granule: gnuplot body of fig2.7-settle_data.gp (run inside this folder); granule plot DIR redraws it
set key below height 1.5
set xlabel 't (s)'
set ylabel 'T (m^2/s^2)'
set title 'T(t) from the start of every run (lines: its steady value)' noenhanced
plot 'fig2.7-settle_data.csv' skip 1 using 3:4 with points pt 7 ps 0.3 lc rgb '#1f5fbf' title 'T(t)', '' skip 1 using 3:5 with lines lw 2 lc rgb '#c0392b' title 'steady T (second half)'

