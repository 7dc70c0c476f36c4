// logrid tune --auto: the configuration space swept on a scene's own frames, and the
// fastest exact setting written as a configuration file (logrid/config.hpp).
#pragma once

#include <cstddef>
#include <string>

#include "cli/options.hpp"

namespace logrid::samples {

struct TuneAutoOptions {
  WalkOptions walk;        // the scene, path, frames, size; the tile and reader to start from
  std::size_t repeat = 3;  // interleaved repetitions per stage
  std::string json;        // the whole sweep as JSON
  std::string config;      // the configuration file written (--write-config)
};

// Runs the sweep (stages in tune_auto.cpp), prints each stage and what the scene needed,
// writes the files asked for. Returns the exit code (1 if a run missed a visible object
// under --verify).
int runTuneAuto(const TuneAutoOptions& o);

}  // namespace logrid::samples
