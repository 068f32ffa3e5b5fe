# granule: gnuplot body of fig5.13-P0_data.gp (run inside this folder); granule plot DIR redraws it
array T[8] = ["N = 1000, L = 0.2 m", "N = 2000, L = 0.2 m", "N = 3000, L = 0.2 m", "N = 4000, L = 0.4 m", "N = 8000, L = 0.4 m", "N = 12000, L = 0.4 m", "N = 18000, L = 0.6 m", "N = 27000, L = 0.6 m"]
set datafile separator whitespace
set datafile missing 'nan'
set key below height 1.5 noenhanced
set xlabel 'ln(v / v_{rms})'
set ylabel '-ln(-ln(P / P^{/Symbol \242}))'
set title "fig5.13-P0: P' = P(0) (filled) and A_0 (open), lines fitted over the window" noenhanced
plot for [i=0:7] 'fig5.13-P0_tail.dat' index i using (log($2)):8 with points pt 7 ps 0.5 lc i+1 title T[i+1], for [i=0:7] '' index i using (log($2)):9 with points pt 6 ps 0.5 lc i+1 notitle, for [i=0:7] '' index i using (log($2)):10 with lines lw 2 lc i+1 notitle, for [i=0:7] '' index i using (log($2)):11 with lines lw 2 dt 2 lc i+1 notitle

