#include "cli/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>

#include "cli/report.hpp"

namespace logrid::samples {
namespace {

// Distinct colours (Okabe–Ito and Tableau), so that ten series stay apart.
constexpr const char* kColors[] = {"#d55e00", "#0072b2", "#009e73", "#e69f00", "#cc79a7",
                                   "#56b4e9", "#000000", "#8c564b", "#7f7f7f", "#bcbd22"};
constexpr const char* kBandFill = "#d9d9d9";
constexpr const char* kBandLine = "#636363";
// A panel's size in pixels, and the panels in a row at most.
constexpr int kPanelWidth = 620, kPanelHeight = 480, kPanelsPerRow = 3;
constexpr int kKeyLineHeight = 16;  // a line of the key (font 11)

// gnuplot's string syntax: double quotes, with \ and " escaped; no '_' subscripts.
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

bool runGnuplot(const std::string& script) {
  const std::string command = "gnuplot " + quoted(script) + " 2>&1";
  const int rc = std::system(command.c_str());
  if (rc != 0) {
    std::fprintf(stderr,
                 "plot: gnuplot failed on %s (exit %d); install it with 'apt-get install "
                 "gnuplot-nox' — the data and script are written beside it\n",
                 script.c_str(), rc);
    return false;
  }
  return true;
}

// The smallest positive and the largest finite value of the panels' series (bands
// included); lo stays infinite when there is none.
struct Extent {
  double lo = INFINITY;  // positive values only (what a log scale shows)
  double hi = -INFINITY;
  double min = INFINITY;
};

Extent extentOf(const std::vector<PlotPanel>& panels) {
  Extent e;
  for (const PlotPanel& panel : panels) {
    for (const PlotSeries& s : panel.series) {
      for (const std::vector<double>* values : {&s.y, &s.y_low, &s.y_high}) {
        for (double v : *values) {
          if (!std::isfinite(v)) continue;
          if (v > 0) e.lo = std::min(e.lo, v);
          e.hi = std::max(e.hi, v);
          e.min = std::min(e.min, v);
        }
      }
    }
  }
  return e;
}

// Whether the positive values span more than a decade.
bool spansDecades(const Extent& e) { return std::isfinite(e.lo) && e.hi > 10 * e.lo; }

// One data block: x, y (and low, high for a band) per line; points a log scale cannot
// show are left out.
std::string dataBlock(const PlotSeries& s, bool log_y) {
  const bool band = !s.y_low.empty();
  std::string data = "# " + s.name + "\n";
  for (std::size_t i = 0; i < s.y.size(); ++i) {
    const double x = s.x.empty() ? double(i) : s.x[i];
    if (log_y && (!(s.y[i] > 0) || (band && !(s.y_low[i] > 0)))) continue;
    data += number(x) + "\t" + number(s.y[i]);
    if (band) data += "\t" + number(s.y_low[i]) + "\t" + number(s.y_high[i]);
    data += "\n";
  }
  return data + "\n\n";  // gnuplot: a new data block
}

// The plot command of one panel whose series are data blocks first_block, first_block+1...
// Bands first, so that the lines are drawn over them.
std::string plotCommand(const std::string& file, const std::vector<PlotSeries>& series,
                        std::size_t first_block) {
  std::vector<std::string> bands, lines;
  for (std::size_t s = 0; s < series.size(); ++s) {
    const std::string block = file + " index " + std::to_string(first_block + s);
    if (!series[s].y_low.empty()) {
      bands.push_back(block + " using 1:3:4 with filledcurves fc rgb " + quoted(kBandFill) +
                      " fs solid noborder title " +
                      quoted(series[s].name + " (fastest to slowest)"));
      lines.push_back(block + " using 1:2 with lines lw 2 lc rgb " + quoted(kBandLine) + " title " +
                      quoted(series[s].name));
      continue;
    }
    const std::size_t c = lines.size();
    lines.push_back(block + " using 1:2 with linespoints pt " + std::to_string(5 + c % 4) +
                    " ps 0.7 lw 2 lc rgb " + quoted(kColors[c % std::size(kColors)]) + " dt " +
                    std::to_string(1 + c / std::size(kColors)) + " title " +
                    quoted(series[s].name));
  }
  std::string plot = "plot ";
  bands.insert(bands.end(), lines.begin(), lines.end());
  for (std::size_t i = 0; i < bands.size(); ++i) plot += (i ? ", \\\n     " : "") + bands[i];
  return plot + "\n";
}

// The x axis's settings, shared by every panel.
std::string xSettings(const PlotAxes& axes) {
  std::string out = "set xlabel " + quoted(axes.xlabel) + "\n";
  if (axes.log_x) out += "set logscale x 2\n";
  if (!axes.xtics.empty()) {
    out += "set xtics (";
    for (std::size_t i = 0; i < axes.xtics.size(); ++i) {
      out += (i ? ", " : "") + quoted(axes.xtics[i].second) + " " + number(axes.xtics[i].first);
    }
    out += ")\n";
    // Room for the first and last tic's points.
    const auto [lo, hi] =
        std::minmax_element(axes.xtics.begin(), axes.xtics.end(),
                            [](const auto& a, const auto& b) { return a.first < b.first; });
    const double pad = axes.log_x ? 1.25 : 0.25 * std::max(1.0, (hi->first - lo->first) / 4);
    out += axes.log_x
               ? "set xrange [" + number(lo->first / pad) + ":" + number(hi->first * pad) + "]\n"
               : "set xrange [" + number(lo->first - pad) + ":" + number(hi->first + pad) + "]\n";
  }
  return out + "set grid\nset key below samplen 2 noenhanced\n";
}

// A y axis: logarithmic when asked, or by itself where the values span decades; with a
// range when it is shared between panels.
std::string ySettings(const PlotAxes& axes, const Extent& extent, bool log_y, bool ranged) {
  std::string out = "set ylabel " + quoted(axes.ylabel + (log_y ? " (log scale)" : "")) + "\n" +
                    (log_y ? "set logscale y\n" : "unset logscale y\n");
  if (!ranged || !(extent.hi > 0)) return out + "set autoscale y\n";
  if (log_y) {
    return out + "set yrange [" + number(extent.lo / 1.25) + ":" + number(extent.hi * 1.25) + "]\n";
  }
  const double lo = std::min(0.0, extent.min);
  return out + "set yrange [" + number(lo) + ":" + number(extent.hi + 0.05 * (extent.hi - lo)) +
         "]\n";
}

bool logY(const PlotAxes& axes, const Extent& extent) {
  return axes.y_scale == PlotScale::Log ||
         (axes.y_scale == PlotScale::Auto && spansDecades(extent));
}

}  // namespace

bool plotPanels(const std::string& stem, const std::string& title, const PlotAxes& axes,
                const std::vector<PlotPanel>& panels) {
  const int count = std::max(1, int(panels.size()));
  const int columns = std::min(count, kPanelsPerRow);
  const int rows = (count + columns - 1) / columns;
  const bool single = count == 1;
  // Panels side by side share one bottom margin, room for the longest key (an entry a
  // line below the plot; a band has two), so that their plots line up.
  std::size_t entries = 0;
  for (const PlotPanel& panel : panels) {
    std::size_t n = 0;
    for (const PlotSeries& s : panel.series) n += s.y_low.empty() ? 1 : 2;
    entries = std::max(entries, n);
  }
  const int height = kPanelHeight + (single ? 0 : kKeyLineHeight * int(entries));
  std::string data;
  std::string script = "set terminal png size " +
                       std::to_string(single ? 2 * kPanelWidth : columns * kPanelWidth) + "," +
                       std::to_string(rows * height) + " font ',11'\nset output " +
                       quoted(stem + ".png") + "\nset datafile separator '\\t'\n" + xSettings(axes);
  if (single) {
    script += "set title " + quoted(title) + " noenhanced\n";
  } else {
    script += "set multiplot layout " + std::to_string(rows) + "," + std::to_string(columns) +
              " title " + quoted(title) + " noenhanced\n";
  }
  const bool shared = axes.shared_y && !single;
  const Extent all = extentOf(panels);
  if (!single) script += "set bmargin " + std::to_string(4 + entries) + "\n";
  std::size_t block = 0;
  bool any = false;
  for (const PlotPanel& panel : panels) {
    const Extent extent = shared ? all : extentOf({panel});
    const bool log_y = logY(axes, extent);
    if (!single) script += "set title " + quoted(panel.title) + " noenhanced\n";
    script += ySettings(axes, extent, log_y, shared);
    for (const PlotSeries& s : panel.series) data += dataBlock(s, log_y);
    script += plotCommand(quoted(stem + ".dat"), panel.series, block);
    block += panel.series.size();
    any = any || !panel.series.empty();
  }
  if (!single) script += "unset multiplot\n";
  writeText(stem + ".dat", data);
  writeText(stem + ".gp", script);
  return any && runGnuplot(stem + ".gp");
}

bool plotLines(const std::string& stem, const std::string& title, const PlotAxes& axes,
               const std::vector<PlotSeries>& series) {
  return plotPanels(stem, title, axes, {{"", series}});
}

bool plotPoints(const std::string& stem, const std::string& title, const std::string& xlabel,
                const std::string& ylabel, const std::vector<PlotPoint>& points, bool log_x) {
  // Sorted by x so that the front's line runs left to right.
  std::vector<PlotPoint> sorted = points;
  std::sort(sorted.begin(), sorted.end(),
            [](const PlotPoint& a, const PlotPoint& b) { return a.x < b.x; });
  std::string data;
  for (int front = 0; front < 2; ++front) {
    for (const PlotPoint& p : sorted) {
      if (p.highlight != bool(front)) continue;
      data += number(p.x) + "\t" + number(p.y) + "\t" + p.label + "\n";
    }
    data += "\n\n";
  }
  writeText(stem + ".dat", data);
  std::string script = "set terminal png size 1100,560 font ',11'\nset output " +
                       quoted(stem + ".png") + "\nset title " + quoted(title) +
                       " noenhanced\nset xlabel " + quoted(xlabel) + "\nset ylabel " +
                       quoted(ylabel) +
                       "\nset key outside right noenhanced\nset grid\nset datafile separator "
                       "'\\t'\n";
  if (log_x) script += "set logscale x\n";
  const std::string file = quoted(stem + ".dat");
  script += "plot " + file + " index 0 using 1:2 with points pt 7 ps 1.2 title 'dominated', " +
            file + " index 1 using 1:2 with linespoints pt 7 ps 1.5 lw 2 title 'Pareto front', " +
            file + " index 1 using 1:2:3 with labels offset 1,0.6 left font ',9' notitle\n";
  writeText(stem + ".gp", script);
  return runGnuplot(stem + ".gp");
}

}  // namespace logrid::samples
