// Plots through gnuplot (Debian package gnuplot-nox): a data file and a script are
// written beside the PNG so that a plot can be restyled or redrawn by hand.
//
// Made to be read: the x axis can carry the real values as labelled tics (lookahead K
// "1, 4, 16, 64, all", mover counts), the y axis turns logarithmic by itself where the
// values span more than a decade, several panels side by side (small multiples: one per
// reader or method family) keep each to a few lines, and a band draws a floor with its
// spread (the oracle's frame time from its fastest to its slowest repetition).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace logrid::samples {

struct PlotSeries {
  std::string name;
  std::vector<double> y;
  std::vector<double> x;  // empty: 0, 1, 2, ...
  // When set (as long as y): a band from y_low to y_high drawn under the lines, with y
  // as its middle line.
  std::vector<double> y_low;
  std::vector<double> y_high;
};

struct PlotPanel {
  std::string title;  // over the panel; unused for a plot of one panel
  std::vector<PlotSeries> series;
};

// Auto: log in a panel whose positive values span more than a decade.
enum class PlotScale { Linear, Log, Auto };

struct PlotAxes {
  std::string xlabel;
  std::string ylabel;  // " (log scale)" is added when the y axis is logarithmic
  PlotScale y_scale = PlotScale::Auto;
  bool log_x = false;
  // Tics at these x values with these labels (e.g. positions 0..4 labelled with the K
  // they stand for); empty: gnuplot's own.
  std::vector<std::pair<double, std::string>> xtics;
  // Panels of one quantity share their y axis (its scale and range), so that they compare
  // at a glance; panels of different quantities (false) have their own.
  bool shared_y = true;
};

// Writes STEM.dat, STEM.gp and, if gnuplot runs, STEM.png: the panels side by side (three
// to a row), one line per series. Returns false (after a warning on stderr) when gnuplot is
// missing or fails, or when there is nothing to draw; the data and script are written
// either way. On a log scale values that are not positive are left out.
bool plotPanels(const std::string& stem, const std::string& title, const PlotAxes& axes,
                const std::vector<PlotPanel>& panels);

// One panel.
bool plotLines(const std::string& stem, const std::string& title, const PlotAxes& axes,
               const std::vector<PlotSeries>& series);

// Points with a label each (e.g. a Pareto plot: time vs error).
struct PlotPoint {
  double x = 0;
  double y = 0;
  std::string label;
  bool highlight = false;  // drawn as part of the front
};
bool plotPoints(const std::string& stem, const std::string& title, const std::string& xlabel,
                const std::string& ylabel, const std::vector<PlotPoint>& points, bool log_x);

}  // namespace logrid::samples
