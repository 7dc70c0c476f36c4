// Runs several configurations over the same frames, interleaved: for each repetition,
// for each frame, every configuration renders that frame in turn. Machine drift and
// noise then hit every configuration alike; per frame the median over repetitions is
// kept, and the spread of the per-repetition averages is reported. The first
// repetition also checks every frame against the object-ID oracle (not timed).
#pragma once

#include <string>
#include <vector>

#include "cli/frame_runner.hpp"

namespace logrid::samples {

// The most repetitions (and warm-up frames) the commands take.
inline constexpr std::size_t kMaxRepeats = 1000;

struct ConfigResult {
  RunConfig config;
  std::vector<FrameRecord> records;   // the first repetition (statistics, oracle counts)
  std::vector<double> frame_ms;       // per frame: median over repetitions
  std::vector<double> frame_ms_low;   // per frame: fastest repetition
  std::vector<double> frame_ms_high;  // per frame: slowest repetition
  std::vector<double> repetition_ms;  // per repetition: average frame time
  double avg_ms() const;              // average of frame_ms
  double spread() const;              // (max - min) / median of repetition_ms
};

// `label` prefixes the progress line. `warmup` frames are rendered first by every
// configuration and discarded (llvmpipe compiles shaders for each new state, docs/PLATFORM.md).
std::vector<ConfigResult> runInterleaved(const PreparedScene& scene, gl::MeshRenderer& renderer,
                                         const std::vector<RunConfig>& configs, std::size_t repeats,
                                         const std::string& label, std::size_t warmup = 2);

}  // namespace logrid::samples
