# granule: gnuplot body of fig2.8_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator ','
set key below height 1.5
set xlabel 'sampling time t (s)'
set ylabel 'T (m^2/s^2)'
set title 'Means over 20 s (points) and the running average (lines), every seed' noenhanced
plot 'fig2.8_data.csv' skip 1 using 3:4 with points pt 7 ps 0.6 lc rgb '#1f5fbf' title 'period means', '' skip 1 using 3:5 with lines lw 2 lc rgb '#c0392b' title 'running average'

