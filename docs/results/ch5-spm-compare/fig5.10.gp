# granule: gnuplot body of fig5.10.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Fraction of the P(v) tail bins (v >= 2 v_rms) where the run and the vertically scaled SPM agree within 3 sigma" noenhanced
set ylabel 'fraction' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'N, L (m)' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig5.10_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule'

