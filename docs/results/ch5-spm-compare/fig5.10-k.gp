# granule: gnuplot body of fig5.10-k.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Vertical scale k of the SPM curve (the vertical scaling of the thesis's Fig. 5.10)" noenhanced
set ylabel 'k' noenhanced
set xlabel 'N' noenhanced
set key below height 1.5
set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot for [i=0:1] 'fig5.10-k_compare.dat' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title columnheader(1)

