# granule: gnuplot body of fig5.6_data.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set logscale xy
set format y '10^{%L}'
set format x '%g'
set xlabel 'v / v_rms' noenhanced
set ylabel '-ln(P(v)/P(0))' noenhanced
set key below height 1.5 noenhanced
set multiplot layout 1,1 title "-ln(P(v)/P(0)) against v/v_rms (Moon, Swift and Swinney), L = 0.4 m, eps_t = 1" noenhanced font ',13'
plot for [i=0:3] 'fig5.6_blocks.dat' index i using 1:2 with points pt 7 ps 0.5 lc i-0+1 title columnheader(1), for [i=0:3] 'fig5.6_overlay.dat' index i using 1:2 with lines dt 2 lw 2 lc i-0+1 title (i == 0 ? 'alpha = 1.5 fitted (dashed)' : '')
unset multiplot

