# granule: gnuplot body of table3.1_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set xlabel 'N' noenhanced
set ylabel '<R^m> of the neighbour separation (m^m)' noenhanced
set key at screen 0.97, 0.06 right bottom font ',12' noenhanced
set tics font ',10'
set title font ',12'
set xlabel font ',11'
set ylabel font ',11'
set multiplot layout 3,3 title "zeta_m: the data of each fit" noenhanced font ',13'
set title 'eps_n = 0.01' noenhanced
plot for [i=0:4] 'table3.1_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i-0+1 title sprintf('m = %d', 1 + (i - 0) * 1), for [i=0:4] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i-0+1 notitle, for [i=0:4] 'table3.1_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i-0+1 title (i == 0 ? 'thesis exponent (dashed)' : '')
unset key
set title 'eps_n = 0.1' noenhanced
plot for [i=5:9] 'table3.1_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i-5+1 title sprintf('m = %d', 1 + (i - 5) * 1), for [i=5:9] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i-5+1 notitle, for [i=5:9] 'table3.1_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i-5+1 title (i == 5 ? 'thesis exponent (dashed)' : '')
set title 'eps_n = 0.3' noenhanced
plot for [i=10:14] 'table3.1_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i-10+1 title sprintf('m = %d', 1 + (i - 10) * 1), for [i=10:14] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i-10+1 notitle, for [i=10:14] 'table3.1_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i-10+1 title (i == 10 ? 'thesis exponent (dashed)' : '')
set title 'eps_n = 0.5' noenhanced
plot for [i=15:19] 'table3.1_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i-15+1 title sprintf('m = %d', 1 + (i - 15) * 1), for [i=15:19] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i-15+1 notitle, for [i=15:19] 'table3.1_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i-15+1 title (i == 15 ? 'thesis exponent (dashed)' : '')
set title 'eps_n = 0.7' noenhanced
plot for [i=20:24] 'table3.1_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i-20+1 title sprintf('m = %d', 1 + (i - 20) * 1), for [i=20:24] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i-20+1 notitle, for [i=20:24] 'table3.1_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i-20+1 title (i == 20 ? 'thesis exponent (dashed)' : '')
set title 'eps_n = 0.9' noenhanced
plot for [i=25:29] 'table3.1_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i-25+1 title sprintf('m = %d', 1 + (i - 25) * 1), for [i=25:29] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i-25+1 notitle, for [i=25:29] 'table3.1_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i-25+1 title (i == 25 ? 'thesis exponent (dashed)' : '')
set title 'eps_n = 0.99' noenhanced
plot for [i=30:34] 'table3.1_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i-30+1 title sprintf('m = %d', 1 + (i - 30) * 1), for [i=30:34] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i-30+1 notitle, for [i=30:34] 'table3.1_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i-30+1 title (i == 30 ? 'thesis exponent (dashed)' : '')
unset multiplot

