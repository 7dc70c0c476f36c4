// logrid bench --traversal: the lazy grid's variants with every depth source, every
// lookahead K and temporal coherence off and on, on the same frames as the oracle:
// flushes, batches, bytes read, objects drawn and frame time per setting, the fastest
// exact setting, and plots of flushes and frame time against K.
#pragma once

#include <string>
#include <vector>

#include "cli/common.hpp"

namespace logrid::samples {

struct TraversalSweepOptions {
  std::vector<std::string> scenes;
  std::vector<std::string> sizes;  // the first is used
  std::vector<std::string> methods{"log-state", "log-zfar"};
  std::vector<std::string> readers;
  std::vector<std::string> lookaheads{"1", "4", "16", "64", "all"};
  double forest_scale = 0;
  double city_scale = 0;
  std::size_t repeat = 2;
  std::string markdown;
  std::string json;
  std::string plots;
};

// Returns the exit code.
int runTraversalSweep(const WalkOptions& base, const TraversalSweepOptions& options);

}  // namespace logrid::samples
