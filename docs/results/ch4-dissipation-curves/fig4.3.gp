# granule: gnuplot body of fig4.3.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "S(k), L = 0.4 m, eps_t = 1 (Case I)" noenhanced
set ylabel 'slope of ln(S(k)) against ln(k d), 0.04-0.165' noenhanced
set xtics rotate by -40 noenhanced
set xlabel 'eps_n, eps_t' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'fig4.3_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule'

