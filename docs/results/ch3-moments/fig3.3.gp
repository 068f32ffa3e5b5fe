# granule: gnuplot body of fig3.3.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set format x '%g'
set xlabel '1 - eps_n^2' noenhanced
set ylabel '<v^2> N^xi_2 (m2 s-2)' noenhanced
set key below height 1.5 noenhanced
set title "<v^2> N^xi_2(eps) against 1 - eps^2, one series per N: the collapse of sec. 3.1.3 (Fig. 3.3)" noenhanced
plot for [i=0:4] 'fig3.3_series.dat' index i using 1:2:3 with yerrorlines pt 7 lc i+1 title columnheader(1)

