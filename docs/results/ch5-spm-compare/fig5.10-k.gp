# granule: gnuplot body of fig5.10-k.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Vertical scale k of the SPM curve (the vertical scaling of the thesis's Fig. 5.10)" noenhanced
set ylabel 'k' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'N, L (m)' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig5.10-k_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule'

