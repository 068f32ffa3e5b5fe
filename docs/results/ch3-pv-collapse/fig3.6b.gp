# granule: gnuplot body of fig3.6b.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "P(v) at eps = 0.1 over N = 100-1585, the speed scaled by <|v|^7>^(1/7) (Fig. 3.6b)" noenhanced
set ylabel 'slope of ln(P(v) <|v|^7>^(1/7)) against ln(v / <|v|^7>^(1/7)), 0.5-1.5' noenhanced
set xlabel 'N' noenhanced
set key below height 1.5
set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot for [i=0:0] 'fig3.6b_compare.dat' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title columnheader(1)

