# granule: gnuplot body of models-freepath-Df_data.gp (run inside this folder); granule plot DIR redraws it
array T[4] = ["normal = hard_sphere, tangential = none, rotation = true, kind = event, beta = -0.1, rolling = none", "normal = spring_dashpot, tangential = tangential_dashpot, rotation = true, kind = verlet, beta = -1, rolling = rolling_friction", "normal = spring_dashpot, tangential = tangential_spring, rotation = false, kind = verlet, beta = -1, rolling = none", "normal = spring_dashpot, tangential = tangential_spring, rotation = true, kind = verlet, beta = -1, rolling = none"]
set datafile separator whitespace
set datafile missing 'nan'
set logscale y
set format y '10^{%L}'
set key below height 1.5 noenhanced maxcols 1 font ',11'
set xlabel '|v| (m/s)'
set ylabel 'P(v) (s/m)'
set title "models-freepath-Df: the runs' P(v), 5.31 with the predicted S (solid) and fitted (dashed)" noenhanced
plot for [i=0:3] 'models-freepath-Df_tail.dat' index i using 1:3 with points pt 7 ps 0.4 lc i+1 title T[i+1], for [i=0:3] '' index i using 1:7 with lines lw 2 lc i+1 notitle, for [i=0:3] '' index i using 1:6 with lines lw 1 dt 2 lc i+1 notitle

