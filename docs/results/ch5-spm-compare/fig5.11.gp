# granule: gnuplot body of fig5.11.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Gaussian tail coefficient b of Q(v,l) in a disc of fixed radius l (5.12), u_l Q = A exp(-b w^2) over w >= 2.5" noenhanced
set ylabel 'b' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'l' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig5.11_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule', '' using ($1+0.15):5:6 with yerrorbars pt 6 ps 1.2 lc rgb '#c0392b' title 'thesis'

