// Summaries of runs as JSON (the contract other tools read, see README "logrid walk").
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "cli/frame_runner.hpp"

namespace logrid::samples {

nlohmann::json frameJson(const FrameRecord& r);

// The summary of one run: averages over `records` (all given frames), sums of the
// oracle counts, and the per-frame array when `per_frame`.
nlohmann::json runSummary(const std::vector<FrameRecord>& records, const RunConfig& config,
                          bool per_frame);

double median(std::vector<double> values);

// Writes a text file; throws logrid::Error(Environment) naming the path.
void writeText(const std::string& path, const std::string& text);

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

}  // namespace logrid::samples
