#include "viewer/frame_stats.hpp"

namespace logrid::viewer {

FrameSample FrameSample::of(const samples::FrameRecord& r, double time, double loop_ms) {
  FrameSample s;
  s.time = time;
  s.cull_ms = r.ms;
  s.loop_ms = loop_ms;
  s.objects = double(r.stats.objects_drawn);
  s.triangles = double(r.triangles);
  s.pixels_read = double(r.stats.pixels_read);
  s.tiles_per_box = r.stats.tilesPerBox();
  s.boxes_tested = double(r.stats.boxes_tested);
  s.flushes = double(r.stats.flushes);
  s.batches = double(r.stats.batches);
  s.queries = double(r.stats.queries);
  s.visible = double(r.visible);
  s.missed = double(r.missed);
  return s;
}

void RollingStats::add(const FrameSample& sample) {
  samples_.push_back(sample);
  while (samples_.size() > 1 && samples_.front().time <= sample.time - kWindowSeconds) {
    samples_.pop_front();
  }
}

FrameSample RollingStats::mean() const {
  FrameSample m;
  if (samples_.empty()) return m;
  bool verified = true;
  double visible = 0, missed = 0;
  for (const FrameSample& s : samples_) {
    m.cull_ms += s.cull_ms;
    m.loop_ms += s.loop_ms;
    m.objects += s.objects;
    m.triangles += s.triangles;
    m.pixels_read += s.pixels_read;
    m.tiles_per_box += s.tiles_per_box;
    m.boxes_tested += s.boxes_tested;
    m.flushes += s.flushes;
    m.batches += s.batches;
    m.queries += s.queries;
    verified = verified && s.visible >= 0;
    visible += s.visible;
    missed += s.missed;
  }
  const double n = double(samples_.size());
  for (double* f : {&m.cull_ms, &m.loop_ms, &m.objects, &m.triangles, &m.pixels_read,
                    &m.tiles_per_box, &m.boxes_tested, &m.flushes, &m.batches, &m.queries}) {
    *f /= n;
  }
  m.visible = verified ? visible / n : -1;
  m.missed = verified ? missed / n : -1;
  m.time = samples_.back().time;
  return m;
}

}  // namespace logrid::viewer
