// logrid bench --tradeoff: the approximate knobs (CullerDesc::approximation) swept on
// the walkthroughs, each setting measured for speed (frame time, ratio to conservative
// LOG) and for error against the full render (objects missed by the oracle, pixels
// differing, PSNR), with a Pareto plot of time against error.
#pragma once

#include <string>
#include <vector>

#include "cli/common.hpp"

namespace logrid::samples {

// Runs the sweep on each scene at the first size; returns the exit code.
int runTradeoff(const WalkOptions& base, const std::vector<std::string>& scenes,
                const std::vector<std::string>& sizes, double forest_scale, double city_scale,
                std::size_t repeats, const std::string& markdown, const std::string& json,
                const std::string& plots);

}  // namespace logrid::samples
