set terminal png size 1100,560 font ',11'
set output "docs/plots/tradeoff_office_640x480.png"
set title "office 640x480: time vs error" noenhanced
set xlabel "pixels differing from the full render, per frame"
set ylabel "frame time / conservative LOG"
set key outside right noenhanced
set grid
set datafile separator '\t'
plot "docs/plots/tradeoff_office_640x480.dat" index 0 using 1:2 with points pt 7 ps 1.2 title 'dominated', "docs/plots/tradeoff_office_640x480.dat" index 1 using 1:2 with linespoints pt 7 ps 1.5 lw 2 title 'Pareto front', "docs/plots/tradeoff_office_640x480.dat" index 1 using 1:2:3 with labels offset 1,0.6 left font ',9' notitle
