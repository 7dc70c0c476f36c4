#include "cli/plot.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iterator>

#include "cli/report.hpp"

namespace logrid::samples {
namespace {

// Distinct colours (Okabe–Ito and Tableau), so that ten series stay apart.
constexpr const char* kColors[] = {"#d55e00", "#0072b2", "#009e73", "#e69f00", "#cc79a7",
                                   "#56b4e9", "#000000", "#8c564b", "#7f7f7f", "#bcbd22"};

// gnuplot's string syntax: double quotes, with \ and " escaped; no '_' subscripts.
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string header(const std::string& stem, const std::string& title, const std::string& xlabel,
                   const std::string& ylabel) {
  return "set terminal png size 1100,560 font ',11'\nset output " + quoted(stem + ".png") +
         "\nset title " + quoted(title) + " noenhanced\nset xlabel " + quoted(xlabel) +
         "\nset ylabel " + quoted(ylabel) +
         "\nset key outside right noenhanced\nset grid\nset datafile separator '\\t'\n";
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

}  // namespace

bool plotLines(const std::string& stem, const std::string& title, const std::string& xlabel,
               const std::string& ylabel, const std::vector<PlotSeries>& series, bool log_y,
               const std::string& settings) {
  std::string data;
  std::string plot = "plot ";
  for (std::size_t s = 0; s < series.size(); ++s) {
    const PlotSeries& ps = series[s];
    data += "# " + ps.name + "\n";
    for (std::size_t i = 0; i < ps.y.size(); ++i) {
      const double x = ps.x.empty() ? double(i) : ps.x[i];
      if (log_y && !(ps.y[i] > 0)) continue;  // log scale: leave zeros out
      char line[96];
      std::snprintf(line, sizeof line, "%.6g\t%.6g\n", x, ps.y[i]);
      data += line;
    }
    data += "\n\n";  // gnuplot: a new data block
    plot += std::string(s ? ", " : "") + quoted(stem + ".dat") + " index " + std::to_string(s) +
            " using 1:2 with linespoints pt " + std::to_string(5 + s % 4) + " ps 0.6 lw 2 lc rgb " +
            quoted(kColors[s % std::size(kColors)]) + " dt " +
            std::to_string(1 + s / std::size(kColors)) + " title " + quoted(ps.name);
  }
  writeText(stem + ".dat", data);
  std::string script = header(stem, title, xlabel, ylabel);
  if (log_y) script += "set logscale y\n";
  writeText(stem + ".gp", script + settings + plot + "\n");
  return !series.empty() && runGnuplot(stem + ".gp");
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
      char line[96];
      std::snprintf(line, sizeof line, "%.6g\t%.6g\t", p.x, p.y);
      data += line + p.label + "\n";
    }
    data += "\n\n";
  }
  writeText(stem + ".dat", data);
  std::string script = header(stem, title, xlabel, ylabel);
  if (log_x) script += "set logscale x\n";
  const std::string file = quoted(stem + ".dat");
  script += "plot " + file + " index 0 using 1:2 with points pt 7 ps 1.2 title 'dominated', " +
            file + " index 1 using 1:2 with linespoints pt 7 ps 1.5 lw 2 title 'Pareto front', " +
            file + " index 1 using 1:2:3 with labels offset 1,0.6 left font ',9' notitle\n";
  writeText(stem + ".gp", script);
  return runGnuplot(stem + ".gp");
}

}  // namespace logrid::samples
