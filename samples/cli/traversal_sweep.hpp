// logrid bench --traversal: the lazy grid's variants with every depth source, every
// lookahead K and temporal coherence off and on, on the same frames as the oracle:
// flushes, batches, bytes read, objects drawn and frame time per setting, the fastest
// exact setting, and plots of flushes and frame time against K, a panel per reader.
#pragma once

#include <string>
#include <vector>

#include "cli/experiment.hpp"

namespace logrid::samples {

// Runs methods × readers × lookaheads × coherence off and on, and the oracle, on each
// scene at the first size, every frame checked against the oracle; returns the exit code.
int runTraversalSweep(const ExperimentOptions& options, const std::vector<std::string>& methods,
                      const std::vector<std::string>& readers,
                      const std::vector<std::string>& lookaheads);

}  // namespace logrid::samples
