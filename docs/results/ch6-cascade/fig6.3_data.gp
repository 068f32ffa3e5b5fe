# granule: gnuplot body of fig6.3_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator ','
set size ratio -1
unset key
set xlabel 'x (m)'
set ylabel 'y (m)'
set multiplot layout 1,2 title 'The same system: a snapshot of the RFM (left) and discs placed from a multiplicative cascade (right)' noenhanced
plot 'fig6.3_positions.csv' skip 1 using 2:(strcol(1) eq 'rfm' ? $3 : 1/0) with points pt 7 ps 0.5 lc rgb '#1f5fbf'
plot 'fig6.3_positions.csv' skip 1 using 2:(strcol(1) eq 'cascade' ? $3 : 1/0) with points pt 7 ps 0.5 lc rgb '#c0392b'
unset multiplot

