set terminal png size 1240,576 font ',11'
set output "/tmp/trav_plots/traversal_city_640x480_ms.png"
set datafile separator '\t'
set xlabel "lookahead K"
set xtics ("1" 0, "16" 1, "64" 2, "256" 3)
set xrange [-0.25:3.25]
set grid
set key below samplen 2 noenhanced
set multiplot layout 1,2 title "city 640x480: frame time against lookahead K" noenhanced
set bmargin 10
set title "reader readpixels" noenhanced
set ylabel "ms per frame"
unset logscale y
set yrange [0:94.2996]
plot "/tmp/trav_plots/traversal_city_640x480_ms.dat" index 4 using 1:3:4 with filledcurves fc rgb "#d9d9d9" fs solid noborder title "oracle (fastest to slowest)", \
     "/tmp/trav_plots/traversal_city_640x480_ms.dat" index 0 using 1:2 with linespoints pt 5 ps 0.7 lw 2 lc rgb "#d55e00" dt 1 title "log-state", \
     "/tmp/trav_plots/traversal_city_640x480_ms.dat" index 1 using 1:2 with linespoints pt 6 ps 0.7 lw 2 lc rgb "#0072b2" dt 1 title "log-state tc", \
     "/tmp/trav_plots/traversal_city_640x480_ms.dat" index 2 using 1:2 with linespoints pt 7 ps 0.7 lw 2 lc rgb "#009e73" dt 1 title "log-zfar", \
     "/tmp/trav_plots/traversal_city_640x480_ms.dat" index 3 using 1:2 with linespoints pt 8 ps 0.7 lw 2 lc rgb "#e69f00" dt 1 title "log-zfar tc", \
     "/tmp/trav_plots/traversal_city_640x480_ms.dat" index 4 using 1:2 with lines lw 2 lc rgb "#636363" title "oracle"
set title "reader pbo" noenhanced
set ylabel "ms per frame"
unset logscale y
set yrange [0:94.2996]
plot "/tmp/trav_plots/traversal_city_640x480_ms.dat" index 9 using 1:3:4 with filledcurves fc rgb "#d9d9d9" fs solid noborder title "oracle (fastest to slowest)", \
     "/tmp/trav_plots/traversal_city_640x480_ms.dat" index 5 using 1:2 with linespoints pt 5 ps 0.7 lw 2 lc rgb "#d55e00" dt 1 title "log-state", \
     "/tmp/trav_plots/traversal_city_640x480_ms.dat" index 6 using 1:2 with linespoints pt 6 ps 0.7 lw 2 lc rgb "#0072b2" dt 1 title "log-state tc", \
     "/tmp/trav_plots/traversal_city_640x480_ms.dat" index 7 using 1:2 with linespoints pt 7 ps 0.7 lw 2 lc rgb "#009e73" dt 1 title "log-zfar", \
     "/tmp/trav_plots/traversal_city_640x480_ms.dat" index 8 using 1:2 with linespoints pt 8 ps 0.7 lw 2 lc rgb "#e69f00" dt 1 title "log-zfar tc", \
     "/tmp/trav_plots/traversal_city_640x480_ms.dat" index 9 using 1:2 with lines lw 2 lc rgb "#636363" title "oracle"
unset multiplot
