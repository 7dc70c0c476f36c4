// Summaries of runs as JSON (the contract other tools read, see README "logrid walk").
#pragma once

#include <nlohmann/json.hpp>

#include <vector>

#include "cli/frame_runner.hpp"

namespace logrid::samples {

nlohmann::json frameJson(const FrameRecord& r);

// The summary of one run: averages over `records` (all given frames), sums of the
// oracle counts, and the per-frame array when `per_frame`.
nlohmann::json runSummary(const std::vector<FrameRecord>& records, const RunConfig& config,
                          bool per_frame);

double median(std::vector<double> values);

}  // namespace logrid::samples
