// logrid bench --motion: the hierarchies for moving objects (bvh/motion.hpp) side by
// side on the forest and the city with N movers each (N from --movers-list): per
// hierarchy the update cost per frame, the statistics pass, drawn objects and
// triangles, occlusion tests and additional queries, frame time and misses; the
// paper's Table 1 columns as ratios (ternary tree against the binary tree of the old
// algorithm, and against refit); plots against the number of movers; and where the
// targets of the motion issue stand (docs/MOTION.md).
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "cli/experiment.hpp"

namespace logrid::samples {

struct MotionBenchOptions {
  bool enabled = false;
  std::string movers = "0,100,1000,10000";
  std::string hierarchies = "refit,rebuild,ternary,ternary-objects,binary";
  std::string method = "log-state";
};

// Adds --motion, --movers-list, --hierarchies and --motion-method to `bench`.
void addMotionBenchOptions(CLI::App& bench, MotionBenchOptions& o);

// Runs it with the rest of bench's options; returns the exit code (1 if a conservative run
// missed a visible object).
int runMotionBench(const ExperimentOptions& options, const MotionBenchOptions& motion);

}  // namespace logrid::samples
