# granule: gnuplot body of fig4.1.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "S(k) at phi = 0.088 as the box grows, L = 0.2-1.2 m (Fig. 4.1)" noenhanced
set ylabel 'slope of ln(S(k)) against ln(k d), 0.01-0.057' noenhanced
set xlabel 'L (m)' noenhanced
set key below height 1.5
set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot for [i=0:0] 'fig4.1_compare.dat' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title columnheader(1)

