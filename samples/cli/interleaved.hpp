// Runs several configurations over the same frames, interleaved: for each repetition,
// for each frame, every configuration renders that frame in turn. Machine drift and
// noise then hit every configuration alike; per frame the median over repetitions is
// kept, and the spread of the per-repetition averages is reported. The first
// repetition also checks every frame against the object-ID oracle (not timed).
//
// Verification must not change what is timed (frame_runner.hpp). With two repetitions or
// more this is checked: the second repetition verifies again every odd frame, each with
// its own ID pass, and leaves the even frames alone; VerificationCheck compares the two.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cli/frame_runner.hpp"

namespace logrid::samples {

// The most repetitions (and warm-up frames) the commands take.
inline constexpr std::size_t kMaxRepeats = 1000;

// A configuration's timed frames with and without the object-ID check after them. The
// first repetition verifies every frame, the second only the odd ones: the odd frames,
// verified in both, give the drift between the two repetitions; the even frames, verified
// in the first only, give that drift times what verification changes.
struct VerificationCheck {
  bool measured = false;     // needs 2 repetitions or more and a verified configuration
  double verified_ms = 0;    // the even frames, verified: their first-repetition times
                             // times the drift
  double unverified_ms = 0;  // the same frames unverified: their second-repetition times
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
  std::vector<double> frame_ms;       // per frame: median over repetitions
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

}  // namespace logrid::samples
