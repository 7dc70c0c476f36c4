set terminal png size 1860,544 font ',11'
set output "/tmp/trav_plots/traversal_forest_640x480_flushes.png"
set datafile separator '\t'
set xlabel "lookahead K"
set xtics ("1" 0, "4" 1, "16" 2, "32" 3, "64" 4)
set xrange [-0.25:4.25]
set grid
set key below samplen 2 noenhanced
set multiplot layout 1,3 title "forest 640x480: flushes per frame against lookahead K" noenhanced
set bmargin 8
set title "reader readpixels" noenhanced
set ylabel "flushes per frame (log scale)"
set logscale y
set yrange [3.70667:72.4167]
plot "/tmp/trav_plots/traversal_forest_640x480_flushes.dat" index 0 using 1:2 with linespoints pt 5 ps 0.7 lw 2 lc rgb "#d55e00" dt 1 title "log-state", \
     "/tmp/trav_plots/traversal_forest_640x480_flushes.dat" index 1 using 1:2 with linespoints pt 6 ps 0.7 lw 2 lc rgb "#0072b2" dt 1 title "log-state tc", \
     "/tmp/trav_plots/traversal_forest_640x480_flushes.dat" index 2 using 1:2 with linespoints pt 7 ps 0.7 lw 2 lc rgb "#009e73" dt 1 title "log-zfar", \
     "/tmp/trav_plots/traversal_forest_640x480_flushes.dat" index 3 using 1:2 with linespoints pt 8 ps 0.7 lw 2 lc rgb "#e69f00" dt 1 title "log-zfar tc"
set title "reader pbo" noenhanced
set ylabel "flushes per frame (log scale)"
set logscale y
set yrange [3.70667:72.4167]
plot "/tmp/trav_plots/traversal_forest_640x480_flushes.dat" index 4 using 1:2 with linespoints pt 5 ps 0.7 lw 2 lc rgb "#d55e00" dt 1 title "log-state", \
     "/tmp/trav_plots/traversal_forest_640x480_flushes.dat" index 5 using 1:2 with linespoints pt 6 ps 0.7 lw 2 lc rgb "#0072b2" dt 1 title "log-state tc", \
     "/tmp/trav_plots/traversal_forest_640x480_flushes.dat" index 6 using 1:2 with linespoints pt 7 ps 0.7 lw 2 lc rgb "#009e73" dt 1 title "log-zfar", \
     "/tmp/trav_plots/traversal_forest_640x480_flushes.dat" index 7 using 1:2 with linespoints pt 8 ps 0.7 lw 2 lc rgb "#e69f00" dt 1 title "log-zfar tc"
set title "reader reduce" noenhanced
set ylabel "flushes per frame (log scale)"
set logscale y
set yrange [3.70667:72.4167]
plot "/tmp/trav_plots/traversal_forest_640x480_flushes.dat" index 8 using 1:2 with linespoints pt 5 ps 0.7 lw 2 lc rgb "#d55e00" dt 1 title "log-state", \
     "/tmp/trav_plots/traversal_forest_640x480_flushes.dat" index 9 using 1:2 with linespoints pt 6 ps 0.7 lw 2 lc rgb "#0072b2" dt 1 title "log-state tc", \
     "/tmp/trav_plots/traversal_forest_640x480_flushes.dat" index 10 using 1:2 with linespoints pt 7 ps 0.7 lw 2 lc rgb "#009e73" dt 1 title "log-zfar", \
     "/tmp/trav_plots/traversal_forest_640x480_flushes.dat" index 11 using 1:2 with linespoints pt 8 ps 0.7 lw 2 lc rgb "#e69f00" dt 1 title "log-zfar tc"
unset multiplot
