# granule: gnuplot body of tableA.1-fit.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "alpha of the free stretched-exponential fit (A.8) over counts 50-5000 (Table A.1)" noenhanced
set ylabel 'alpha' noenhanced
set xlabel 'eps_n' noenhanced
set key below height 1.5
set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06
set grid ytics lc rgb '#dddddd'
plot for [i=0:1] 'tableA.1-fit_compare.dat' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title columnheader(1), for [i=0:1] '' index i using 1:4:5 with yerrorbars pt 6 ps 2 lc i+1 notitle, NaN with points pt 6 ps 2 lc rgb 'black' title 'thesis (open)'

