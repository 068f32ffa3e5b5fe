# granule: gnuplot body of fig3.5_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set xlabel 'N' noenhanced
set ylabel '<|v|^m> ((m/s)^m)' noenhanced
set key at screen 0.97, 0.06 right bottom font ',12' noenhanced
set tics font ',10'
set title font ',12'
set xlabel font ',11'
set ylabel font ',11'
set multiplot layout 3,3 title "xi_m/m: the data of each fit (open: outside the fit window N >= 251)" noenhanced font ',13'
set title 'eps_n = 0.01' noenhanced
plot for [i=0:8] 'fig3.5_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i-0+1 title sprintf('m = %d', 1 + (i - 0) * 1), for [i=0:8] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i-0+1 notitle, for [i=0:8] 'fig3.5_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i-0+1 title (i == 0 ? 'thesis exponent (dashed)' : '')
unset key
set title 'eps_n = 0.1' noenhanced
plot for [i=9:17] 'fig3.5_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i-9+1 title sprintf('m = %d', 1 + (i - 9) * 1), for [i=9:17] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i-9+1 notitle, for [i=9:17] 'fig3.5_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i-9+1 title (i == 9 ? 'thesis exponent (dashed)' : '')
set title 'eps_n = 0.3' noenhanced
plot for [i=18:26] 'fig3.5_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i-18+1 title sprintf('m = %d', 1 + (i - 18) * 1), for [i=18:26] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i-18+1 notitle, for [i=18:26] 'fig3.5_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i-18+1 title (i == 18 ? 'thesis exponent (dashed)' : '')
set title 'eps_n = 0.5' noenhanced
plot for [i=27:35] 'fig3.5_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i-27+1 title sprintf('m = %d', 1 + (i - 27) * 1), for [i=27:35] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i-27+1 notitle, for [i=27:35] 'fig3.5_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i-27+1 title (i == 27 ? 'thesis exponent (dashed)' : '')
set title 'eps_n = 0.7' noenhanced
plot for [i=36:44] 'fig3.5_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i-36+1 title sprintf('m = %d', 1 + (i - 36) * 1), for [i=36:44] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i-36+1 notitle, for [i=36:44] 'fig3.5_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i-36+1 title (i == 36 ? 'thesis exponent (dashed)' : '')
set title 'eps_n = 0.9' noenhanced
plot for [i=45:53] 'fig3.5_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i-45+1 title sprintf('m = %d', 1 + (i - 45) * 1), for [i=45:53] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i-45+1 notitle, for [i=45:53] 'fig3.5_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i-45+1 title (i == 45 ? 'thesis exponent (dashed)' : '')
set title 'eps_n = 0.99' noenhanced
plot for [i=54:62] 'fig3.5_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i-54+1 title sprintf('m = %d', 1 + (i - 54) * 1), for [i=54:62] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i-54+1 notitle, for [i=54:62] 'fig3.5_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i-54+1 title (i == 54 ? 'thesis exponent (dashed)' : '')
unset multiplot

