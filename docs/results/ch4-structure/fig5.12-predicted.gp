# granule: gnuplot body of fig5.12-predicted.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Predicted tail coefficient S of P(v) ~ exp(-S |v|^alpha) (5.27) from each run's C, D_f = 1.63" noenhanced
set ylabel 'S / (m/s)^-0.972' noenhanced
set xlabel 'N' noenhanced
set logscale x
set key below height 1.5
set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot for [i=0:2] 'fig5.12-predicted_compare.dat' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title columnheader(1), for [i=0:2] '' index i using 1:4:5 with yerrorbars pt 6 ps 2 lc i+1 notitle, NaN with points pt 6 ps 2 lc rgb 'black' title 'thesis (open)'

