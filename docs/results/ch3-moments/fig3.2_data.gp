# granule: gnuplot body of fig3.2_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set xlabel 'N' noenhanced
set ylabel '<v^2> (m^2/s^2)' noenhanced
set key below height 1.5 noenhanced
set multiplot layout 1,1 title "xi_2: the data of each fit (open: outside the fit window N >= 398)" noenhanced font ',13'
plot for [i=0:6] 'fig3.2_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i+1 title columnheader(1), for [i=0:6] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i+1 notitle, for [i=0:6] 'fig3.2_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i+1 title (i == 0 ? 'thesis exponent (dashed)' : '')
unset multiplot

