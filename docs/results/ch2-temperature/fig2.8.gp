# granule: gnuplot body of fig2.8.gp (run inside this folder); granule plot DIR redraws it
set datafile separator whitespace
set title "Time average of T over 20 s periods and its running average" noenhanced
set ylabel '<T> / m^2/s^2' noenhanced
set xtics rotate by -40 noenhanced
set key below height 1.5
set offsets 0.5, 0.5, 0, 0
set grid ytics lc rgb '#dddddd'
plot 'fig2.8_compare.dat' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title 'granule'

