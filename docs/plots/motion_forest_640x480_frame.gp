set terminal png size 1100,560 font ',11'
set output "docs/plots/motion_forest_640x480_frame.png"
set title "forest 640x480: frame time" noenhanced
set xlabel "movers"
set ylabel "ms"
set key outside right noenhanced
set grid
set datafile separator '\t'
set xtics ("0" 0, "100" 1, "1,000" 2, "10,000" 3)
plot "docs/plots/motion_forest_640x480_frame.dat" index 0 using 1:2 with linespoints pt 5 ps 0.6 lw 2 lc rgb "#d55e00" dt 1 title "refit", "docs/plots/motion_forest_640x480_frame.dat" index 1 using 1:2 with linespoints pt 6 ps 0.6 lw 2 lc rgb "#0072b2" dt 1 title "rebuild", "docs/plots/motion_forest_640x480_frame.dat" index 2 using 1:2 with linespoints pt 7 ps 0.6 lw 2 lc rgb "#009e73" dt 1 title "ternary", "docs/plots/motion_forest_640x480_frame.dat" index 3 using 1:2 with linespoints pt 8 ps 0.6 lw 2 lc rgb "#e69f00" dt 1 title "ternary-objects", "docs/plots/motion_forest_640x480_frame.dat" index 4 using 1:2 with linespoints pt 5 ps 0.6 lw 2 lc rgb "#cc79a7" dt 1 title "binary"
