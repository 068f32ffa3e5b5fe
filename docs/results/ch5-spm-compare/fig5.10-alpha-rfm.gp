# granule: gnuplot body of fig5.10-alpha-rfm.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Tail exponent of the run's P(v), A exp(-(|v|/v0)^alpha) over v >= 2 v_rms (the compared bins)" noenhanced
set ylabel 'alpha' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'N, L (m)' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig5.10-alpha-rfm_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule'

