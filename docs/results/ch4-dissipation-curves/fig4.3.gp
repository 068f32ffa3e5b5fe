# granule: gnuplot body of fig4.3.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "S(k), L = 0.4 m, eps_t = 1 (Case I)" noenhanced
set ylabel 'slope of ln(S(k)) against ln(k d), 0.04-0.165' noenhanced
set xlabel 'eps_n' noenhanced
set key below height 1.5
set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot for [i=0:0] 'fig4.3_compare.dat' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title columnheader(1)

