// Plots through gnuplot (Debian package gnuplot-nox): a data file and a script are
// written beside the PNG so that a plot can be restyled or redrawn by hand.
#pragma once

#include <string>
#include <vector>

namespace logrid::samples {

struct PlotSeries {
  std::string name;
  std::vector<double> y;
  std::vector<double> x;  // empty: 0, 1, 2, ...
};

// Writes STEM.dat, STEM.gp and, if gnuplot runs, STEM.png: one line per series.
// Returns false (after a warning on stderr) when gnuplot is missing or fails; the
// data and script are written either way. `settings`: more gnuplot commands (e.g.
// "set xtics (...)\n"), placed before the plot command.
bool plotLines(const std::string& stem, const std::string& title, const std::string& xlabel,
               const std::string& ylabel, const std::vector<PlotSeries>& series, bool log_y,
               const std::string& settings = "");

// The same with points and a label per point (e.g. a Pareto plot: time vs error).
struct PlotPoint {
  double x = 0;
  double y = 0;
  std::string label;
  bool highlight = false;  // drawn as part of the front
};
bool plotPoints(const std::string& stem, const std::string& title, const std::string& xlabel,
                const std::string& ylabel, const std::vector<PlotPoint>& points, bool log_x);

}  // namespace logrid::samples
