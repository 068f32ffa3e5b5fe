# granule: gnuplot body of fig3.6b.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "P(v) at eps = 0.1 over N = 100-1585, the speed scaled by <|v|^7>^(1/7) (Fig. 3.6b)" noenhanced
set ylabel 'slope of ln(P(v) <|v|^7>^(1/7)) against ln(v / <|v|^7>^(1/7)), 0.5-1.5' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'eps_n, N' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig3.6b_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule'

