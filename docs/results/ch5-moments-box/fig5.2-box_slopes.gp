# granule: gnuplot body of fig5.2-box_slopes.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "The local slopes of xi_m/m against N" noenhanced
set logscale x
set xlabel 'N' noenhanced
set ylabel 'local xi_m/m' noenhanced
set key below height 1.5
set grid ytics lc rgb '#dddddd'
plot 'fig5.2-box_slopes.dat' index 0 using ($1*0.9775):4:2:3:($4-$5):($4+$5) with xyerrorbars pt 7 lc rgb '#0072b2' title 'eps_n = 0.1, m = 3', '' index 1 using 1:2 with lines lc rgb '#0072b2' lw 2 title 'trend (quadratic in ln N)', '' index 2 using 1:2 with lines lc rgb '#0072b2' dt 3 title 'exponent of the whole fit', '' index 3 using 1:2 with lines lc rgb '#c0392b' dt 2 lw 2 title 'thesis', 'fig5.2-box_slopes.dat' index 4 using ($1*0.9925):4:2:3:($4-$5):($4+$5) with xyerrorbars pt 7 lc rgb '#d55e00' title 'eps_n = 0.1, m = 6', '' index 5 using 1:2 with lines lc rgb '#d55e00' lw 2 title '', '' index 6 using 1:2 with lines lc rgb '#d55e00' dt 3 title '', '' index 7 using 1:2 with lines lc rgb '#c0392b' dt 2 lw 2 title '', 'fig5.2-box_slopes.dat' index 8 using ($1*1.0075):4:2:3:($4-$5):($4+$5) with xyerrorbars pt 7 lc rgb '#009e73' title 'eps_n = 0.1, m = 9', '' index 9 using 1:2 with lines lc rgb '#009e73' lw 2 title '', '' index 10 using 1:2 with lines lc rgb '#009e73' dt 3 title '', '' index 11 using 1:2 with lines lc rgb '#c0392b' dt 2 lw 2 title '', 'fig5.2-box_slopes.dat' index 12 using ($1*1.0225):4:2:3:($4-$5):($4+$5) with xyerrorbars pt 7 lc rgb '#cc79a7' title 'eps_n = 0.1, m = 12', '' index 13 using 1:2 with lines lc rgb '#cc79a7' lw 2 title '', '' index 14 using 1:2 with lines lc rgb '#cc79a7' dt 3 title '', '' index 15 using 1:2 with lines lc rgb '#c0392b' dt 2 lw 2 title ''

