# granule: gnuplot body of models-freepath-Df.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "D_f from the free-path tail (4.25), fitted where the thesis fits it (P_l < 1 per metre), under each contact model" noenhanced
set ylabel 'D_f' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'normal, tangential, rotation, kind' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'models-freepath-Df_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule'

