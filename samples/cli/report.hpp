// Reports: writing them (text, JSON), the command line they record, and how their
// numbers are written in Markdown.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace logrid::samples {

// Writes a text file; throws logrid::Error(Environment) naming the path.
void writeText(const std::string& path, const std::string& text);
// Writes JSON to a file; throws logrid::Error(Environment) naming the path.
void writeJson(const std::string& path, const nlohmann::json& json);

// The command line as typed (quoted where needed), recorded by main() for reports.
void setCommandLine(int argc, char** argv);
const std::string& commandLine();

// A number with a fixed count of decimals, e.g. formatFixed(2.345, 1) == "2.3".
std::string formatFixed(double value, int decimals = 2);

// a / b with two decimals and `suffix` (e.g. "×"), or "–" when b is not positive.
std::string formatRatio(double a, double b, const char* suffix = "");

// The path of `target` relative to the folder of `document` (for links in markdown).
std::string linkFrom(const std::string& document, const std::string& target);

// "30 frames along the walkthrough" (spread over all of it), or with a time step (RunConfig::
// time_step) "30 frames 0.040 s of path time apart from the walkthrough's start".
std::string framesAlong(std::size_t frames, double time_step);
// 1234567 -> "1,234,567"
std::string grouped(double value);

// One column of a Markdown table of Rows: its header, its alignment ("---" left, "--:"
// right, ":-:" centred) and what a row shows in it.
template <typename Row>
struct Column {
  std::string header;
  std::string align;
  std::function<std::string(const Row&)> cell;
};

// The table: a header line, the alignment line, a line per row.
template <typename Row>
void writeTable(std::ostream& md, const std::vector<Column<Row>>& columns,
                const std::vector<Row>& rows) {
  std::string header = "|", align = "|";
  for (const Column<Row>& c : columns) header += " " + c.header + " |", align += c.align + "|";
  md << header << "\n" << align << "\n";
  for (const Row& row : rows) {
    md << "|";
    for (const Column<Row>& c : columns) md << " " << c.cell(row) << " |";
    md << "\n";
  }
}

}  // namespace logrid::samples
