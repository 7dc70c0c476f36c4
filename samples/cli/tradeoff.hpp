// logrid bench --tradeoff: the approximate knobs (CullerDesc::approximation) swept on
// the walkthroughs, each setting measured for speed (frame time, ratio to conservative
// LOG) and for error against the full render (objects missed by the oracle, pixels
// differing, PSNR), with a Pareto plot of time against error.
#pragma once

#include <vector>

#include "cli/experiment.hpp"

namespace logrid::samples {

// Runs the sweep on each scene at the first size, every frame checked against the oracle,
// and log-state under each frame-time budget of `budgets_ms` (CullerDesc::budget_ms);
// returns the exit code.
int runTradeoff(const ExperimentOptions& options, const std::vector<double>& budgets_ms = {});

}  // namespace logrid::samples
