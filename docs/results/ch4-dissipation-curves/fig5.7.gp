# granule: gnuplot body of fig5.7.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "-ln(P(v)/P(0)) against v/v_rms (Moon, Swift and Swinney), L = 0.4 m, eps_t = 0.1" noenhanced
set ylabel 'slope of ln(-ln(P(v)/P(0))) against ln(v / v_rms), 2.718-100' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'eps_n, eps_t' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig5.7_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule'

