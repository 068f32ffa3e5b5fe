# granule: gnuplot body of models-Df.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Fractal dimension D_f of S(k) (sec. 4.1) under each contact model" noenhanced
set ylabel 'D_f' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'normal, tangential, rotation, kind, beta, rolling' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'models-Df_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule'

