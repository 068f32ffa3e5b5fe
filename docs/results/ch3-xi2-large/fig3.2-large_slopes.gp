# granule: gnuplot body of fig3.2-large_slopes.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "The local slopes of xi_2 against N" noenhanced
set logscale x
set xlabel 'N' noenhanced
set ylabel 'local xi_2' noenhanced
set key below height 1.5
set grid ytics lc rgb '#dddddd'
plot 'fig3.2-large_slopes.dat' index 0 using ($1*1.0000):4:2:3:($4-$5):($4+$5) with xyerrorbars pt 7 lc rgb '#0072b2' title 'eps_n = 0.1', '' index 1 using ($1*1.0200):4:2:3:($4-$5):($4+$5) with xyerrorbars pt 6 ps 1.5 lc rgb '#0072b2' title 'between sizes 3 apart (open)', '' index 2 using 1:2 with lines lc rgb '#0072b2' lw 2 title 'trend (quadratic in ln N)', '' index 3 using 1:2 with lines lc rgb '#0072b2' dt 3 title 'exponent of the whole fit', '' index 4 using 1:2 with lines lc rgb '#c0392b' dt 2 lw 2 title 'thesis'

