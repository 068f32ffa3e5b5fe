# granule: gnuplot body of fig5.2-box.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Moments of the speed against N at L = 0.4 m (phi = N pi r^2 / L^2): xi_m / m of <|v|^m> ~ N^-xi_m, phi < 0.1" noenhanced
set ylabel 'xi_m/m' noenhanced
set xtics rotate by 90 right font ',11' noenhanced
set xlabel 'eps_n' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig5.2-box_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule', '' using ($1+0.15):5:6 with yerrorbars pt 6 ps 1.2 lc rgb '#c0392b' title 'thesis'

