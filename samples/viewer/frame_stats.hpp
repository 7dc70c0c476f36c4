// The panel's numbers: each frame's, and their average over the last second of viewer
// time.
#pragma once

#include <cstddef>
#include <deque>

#include "cli/frame_runner.hpp"

namespace logrid::viewer {

struct FrameSample {
  double time = 0;     // viewer clock, seconds
  double cull_ms = 0;  // clear + cull + draw + glFinish (FrameRecord::ms, as walk reports)
  double loop_ms = 0;  // the whole viewer frame: input, frame, overlays, panel, swap
  double objects = 0;
  double triangles = 0;
  double pixels_read = 0;
  double tiles_per_box = 0;
  double boxes_tested = 0;
  double flushes = 0;
  double batches = 0;
  double queries = 0;
  double visible = -1;  // with verify, else -1
  double missed = -1;

  static FrameSample of(const samples::FrameRecord& record, double time, double loop_ms);
};

class RollingStats {
 public:
  static constexpr double kWindowSeconds = 1.0;
  void add(const FrameSample& sample);
  // The mean of the samples of the last second (fields of -1 when any sample lacks them).
  FrameSample mean() const;
  const FrameSample* last() const { return samples_.empty() ? nullptr : &samples_.back(); }
  std::size_t count() const { return samples_.size(); }
  void clear() { samples_.clear(); }

 private:
  std::deque<FrameSample> samples_;
};

}  // namespace logrid::viewer
