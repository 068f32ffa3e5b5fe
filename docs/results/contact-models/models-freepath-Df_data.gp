# granule: gnuplot body of models-freepath-Df_data.gp (run inside this folder); granule plot DIR redraws it
array T[5] = ["normal = hard_sphere, tangential = none, rotation = false, kind = event", "normal = hertz, tangential = tangential_dashpot, rotation = false, kind = verlet", "normal = spring_dashpot, tangential = sliding_friction, rotation = true, kind = verlet", "normal = spring_dashpot, tangential = tangential_dashpot, rotation = false, kind = verlet", "normal = spring_dashpot, tangential = tangential_dashpot, rotation = true, kind = verlet"]
set datafile separator whitespace
set datafile missing 'nan'
set logscale y
set format y '10^{%L}'
set key below height 1.5 noenhanced maxcols 1 font ',11'
set xlabel '|v| (m/s)'
set ylabel 'P(v) (s/m)'
set title "models-freepath-Df: the runs' P(v), 5.31 with the predicted S (solid) and fitted (dashed)" noenhanced
plot for [i=0:4] 'models-freepath-Df_tail.dat' index i using 1:3 with points pt 7 ps 0.4 lc i+1 title T[i+1], for [i=0:4] '' index i using 1:7 with lines lw 2 lc i+1 notitle, for [i=0:4] '' index i using 1:6 with lines lw 1 dt 2 lc i+1 notitle

