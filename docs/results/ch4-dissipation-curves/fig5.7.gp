# granule: gnuplot body of fig5.7.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "-ln(P(v)/P(0)) against v/v_rms (Moon, Swift and Swinney), L = 0.4 m, eps_t = 0.1" noenhanced
set ylabel 'slope of ln(-ln(P(v)/P(0))) against ln(v / v_rms), 2.718-100' noenhanced
set xlabel 'eps_n' noenhanced
set key below height 1.5
set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot for [i=0:0] 'fig5.7_compare.dat' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title columnheader(1)

