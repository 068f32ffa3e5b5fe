# granule: gnuplot body of fig5.10.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Fraction of the P(v) tail bins (v >= 2 v_rms) where the run and the vertically scaled SPM agree within 3 sigma" noenhanced
set ylabel 'fraction' noenhanced
set xlabel 'N' noenhanced
set key below height 1.5
set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot for [i=0:1] 'fig5.10_compare.dat' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title columnheader(1)

