# granule: gnuplot body of table5.3-vc.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Crossover velocity v_c / v_r of P_0(v) (5.32), L = 0.4 m" noenhanced
set ylabel 'v_c/v_r' noenhanced
set xlabel 'eps_n' noenhanced
set key below height 1.5
set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot for [i=0:1] 'table5.3-vc_compare.dat' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title columnheader(1), for [i=0:1] '' index i using 1:4:5 with yerrorbars pt 6 ps 2 lc i+1 notitle, NaN with points pt 6 ps 2 lc rgb 'black' title 'thesis (open)'

