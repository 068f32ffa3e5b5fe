# granule: gnuplot body of fig5.12-predicted.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Predicted tail coefficient S of P(v) ~ exp(-S |v|^alpha) (5.27) from each run's C, D_f = 1.63" noenhanced
set ylabel 'S / (m/s)^-0.972' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'N, L (m)' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig5.12-predicted_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule', '' using ($1+0.15):5:6 with yerrorbars pt 6 ps 1.2 lc rgb '#c0392b' title 'thesis'

