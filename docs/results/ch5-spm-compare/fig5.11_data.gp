# granule: gnuplot body of fig5.11_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale y
set format y '10^{%L}'
set key below height 1.5 noenhanced
set xlabel 'w = v / u_l,  u_l = (2 D l / M^2)^{1/3}'
set ylabel 'u_l Q(v, l)'
set title "Q(v,l) of a particle in a disc of fixed radius (Fig. 5.11), collapsed (sec. 5.3.1)" noenhanced
plot for [i=0:3] 'fig5.11_q.dat' index i using 1:2 with points pt 7 ps 0.5 lc i+1 title columnheader(1), (x >= 2.5 ? 0.865172146 * exp(-0.972577993 * x**2) : 1/0) with lines lw 2 lc rgb 'black' title 'pooled fit, b = 0.973', (x >= 2.5 ? 0.00198241549 * exp(-0.98 * x**2 + 0.98 * 2.5**2) : 1/0) with lines dt 2 lw 2 lc rgb '#c0392b' title 'thesis 5.12: b = 0.98'

