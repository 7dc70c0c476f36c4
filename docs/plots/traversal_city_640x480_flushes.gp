set terminal png size 1100,560 font ',11'
set output "docs/plots/traversal_city_640x480_flushes.png"
set title "city 640x480: flushes per frame against lookahead K" noenhanced
set xlabel "K (0 = 1, 1 = 16, 2 = 64, 3 = 256)"
set ylabel "flushes per frame (log scale)"
set key outside right noenhanced
set grid
set datafile separator '\t'
set logscale y
plot "docs/plots/traversal_city_640x480_flushes.dat" index 0 using 1:2 with linespoints pt 5 ps 0.6 lw 2 lc rgb "#d55e00" dt 1 title "log-state readpixels", "docs/plots/traversal_city_640x480_flushes.dat" index 1 using 1:2 with linespoints pt 6 ps 0.6 lw 2 lc rgb "#0072b2" dt 1 title "log-state readpixels tc", "docs/plots/traversal_city_640x480_flushes.dat" index 2 using 1:2 with linespoints pt 7 ps 0.6 lw 2 lc rgb "#009e73" dt 1 title "log-state pbo", "docs/plots/traversal_city_640x480_flushes.dat" index 3 using 1:2 with linespoints pt 8 ps 0.6 lw 2 lc rgb "#e69f00" dt 1 title "log-state pbo tc", "docs/plots/traversal_city_640x480_flushes.dat" index 4 using 1:2 with linespoints pt 5 ps 0.6 lw 2 lc rgb "#cc79a7" dt 1 title "log-zfar readpixels", "docs/plots/traversal_city_640x480_flushes.dat" index 5 using 1:2 with linespoints pt 6 ps 0.6 lw 2 lc rgb "#56b4e9" dt 1 title "log-zfar readpixels tc", "docs/plots/traversal_city_640x480_flushes.dat" index 6 using 1:2 with linespoints pt 7 ps 0.6 lw 2 lc rgb "#000000" dt 1 title "log-zfar pbo", "docs/plots/traversal_city_640x480_flushes.dat" index 7 using 1:2 with linespoints pt 8 ps 0.6 lw 2 lc rgb "#8c564b" dt 1 title "log-zfar pbo tc"
