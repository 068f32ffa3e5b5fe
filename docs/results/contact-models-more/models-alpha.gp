# granule: gnuplot body of models-alpha.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Tail exponent alpha of P(v) = A exp(-(|v|/v0)^alpha) (5.5), free fit, under each contact model" noenhanced
set ylabel 'alpha' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'normal, tangential, rotation, kind, beta, rolling' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'models-alpha_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule'

