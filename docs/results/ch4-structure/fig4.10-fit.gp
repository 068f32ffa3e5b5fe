# granule: gnuplot body of fig4.10-fit.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "D_f from the free-path tail fit (4.25) P_l = A0 exp(-C l^(D_f-1)) l^(D_f-2)" noenhanced
set ylabel 'D_f' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'N, L (m)' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig4.10-fit_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule', '' using ($1+0.15):5:6 with yerrorbars pt 6 ps 1.2 lc rgb '#c0392b' title 'thesis'

