// logrid bench --clusters: the same scene prepared at several granularities (whole
// objects, and clusters of N triangles, samples/scene/clusters.hpp), every method on the
// same frames at each, all interleaved: frame time, ids and objects drawn, triangles,
// draw calls, pixels read and flushes, against the cluster oracle of the same
// granularity and the object oracle (the whole objects' oracle); and what each
// granularity costs to build and to hold.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cli/experiment.hpp"

namespace logrid::samples {

// Runs `methods` (with the oracle, which must be among them for the ratios) on each
// scene at each size, at each granularity in `clusters` (0: whole objects), every frame
// of the first repetition checked against the oracle; returns the exit code.
int runClusterSweep(const ExperimentOptions& options, const std::vector<std::string>& methods,
                    const std::vector<std::uint32_t>& clusters);

}  // namespace logrid::samples
