# granule: gnuplot body of fig5.2-box_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set xlabel 'N' noenhanced
set ylabel '<|v|^m> ((m/s)^m)' noenhanced
set key below height 1.5 noenhanced
set multiplot layout 1,1 title "xi_m/m: the data of each fit (open: outside the fit window N <= 2264)" noenhanced font ',13'
plot for [i=0:3] 'fig5.2-box_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars pt 7 lc i+1 title columnheader(1), for [i=0:3] '' index i using 1:($4 > 0 ? 1/0 : $2) with points pt 6 lc i+1 notitle, for [i=0:3] 'fig5.2-box_thesis.dat' index i using 1:2 with lines dt 2 lw 2 lc i+1 title (i == 0 ? 'thesis exponent (dashed)' : '')
unset multiplot

