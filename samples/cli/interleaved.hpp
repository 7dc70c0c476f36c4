// Runs several configurations over the same frames, interleaved: for each repetition,
// for each frame, every configuration renders that frame in turn. Machine drift and
// noise then hit every configuration alike; per frame the median over repetitions is
// kept, and the spread of the per-repetition averages is reported. The first
// repetition also checks every frame against the object-ID oracle, whose visible sets
// are found before any frame is timed (the ID passes run in a runner of their own).
//
// Verification must not change what is timed (frame_runner.hpp). With two repetitions or
// more this is checked: the second repetition runs its odd frames with ID passes and its
// even frames without (VerificationCheck).
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cli/frame_runner.hpp"

namespace logrid::samples {

// The most repetitions (and warm-up frames) the commands take.
inline constexpr std::size_t kMaxRepeats = 1000;

// Whether the object-ID passes change a configuration's timed frames (they must not,
// frame_runner.hpp). The second repetition runs its odd frames with an ID pass of the
// configuration's own (after a method's frame, as verification does; before the oracle's)
// and its even frames with none; each frame's time is taken against the same frame's
// time in the first repetition, so that neither the frames' own costs nor the drift
// between repetitions (the even frames' ratio) enter.
struct VerificationCheck {
  bool measured = false;     // needs 2 repetitions or more and a verified configuration
  double verified_ms = 0;    // the odd frames of the second repetition, with ID passes
  double unverified_ms = 0;  // the same frames without: their first-repetition times,
                             // times the drift
  double difference = 0;     // verified_ms / unverified_ms - 1
  double noise = 0;          // twice the standard error of `difference` over the frames
  // |difference| beyond the configuration's spread and the noise: verification
  // changes the timed frame (it must not).
  bool flagged(double spread) const {
    return measured && std::abs(difference) > std::max(spread, noise);
  }
};

struct ConfigResult {
  RunConfig config;
  std::vector<FrameRecord> records;   // the first repetition (statistics, oracle counts)
  std::vector<double> frame_ms;       // per frame: median over repetitions (not counting
                                      // the frames run for VerificationCheck)
  std::vector<double> frame_ms_low;   // per frame: fastest repetition
  std::vector<double> frame_ms_high;  // per frame: slowest repetition
  std::vector<double> repetition_ms;  // per repetition: average frame time
  double avg_ms() const;              // average of frame_ms
  double spread() const;              // (max - min) / median of repetition_ms
  VerificationCheck verification;
};

// `label` prefixes the progress line. `warmup` frames are rendered first by every
// configuration and discarded (llvmpipe compiles shaders for each new state, docs/PLATFORM.md).
std::vector<ConfigResult> runInterleaved(const PreparedScene& scene, gl::MeshRenderer& renderer,
                                         const std::vector<RunConfig>& configs, std::size_t repeats,
                                         const std::string& label, std::size_t warmup = 2);

// A configuration on a scene of its own: the same frames of several preparations of one
// scene (whole objects and clusters, say), interleaved alike. Each scene's ID passes are
// its own.
struct SceneConfig {
  const PreparedScene* scene;
  gl::MeshRenderer* renderer;
  RunConfig config;
};
std::vector<ConfigResult> runInterleaved(const std::vector<SceneConfig>& configs,
                                         std::size_t repeats, const std::string& label,
                                         std::size_t warmup = 2);

}  // namespace logrid::samples
