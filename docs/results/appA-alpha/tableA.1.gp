# granule: gnuplot body of tableA.1.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "alpha of the free stretched-exponential fit (A.8) over counts 50-5000 (Table A.1)" noenhanced
set ylabel 'alpha' noenhanced
set xtics rotate by 90 right font ',11' noenhanced
set xlabel 'N, eps_n' noenhanced
set key below height 1.5
set offsets 0.5, 0.5, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot 'tableA.1_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule', '' using ($1+0.15):5:6 with yerrorbars pt 6 ps 1.2 lc rgb '#c0392b' title 'thesis'

