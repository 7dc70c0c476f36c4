#include "cli/summary.hpp"

#include <algorithm>

namespace logrid::samples {

namespace {

// A count that only some frames have, added to its sum (which exists once one has).
template <typename T>
void addPresent(std::optional<T>& sum, T value) {
  sum = sum.value_or(T(0)) + value;
}

// One frame's counts added to the sums (`tiles`: the tiles tested).
void addFrame(const FrameRecord& r, FrameAverages& a, double& tiles) {
  const FrameStats& s = r.stats;
  a.ms += r.ms;
  a.objects += double(s.objects_drawn);
  a.triangles += double(r.triangles);
  a.draw_calls += double(r.draw_calls);
  if (r.objects_drawn >= 0) addPresent(a.cluster_objects, double(r.objects_drawn));
  if (r.visible_objects >= 0) addPresent(a.visible_cluster_objects, r.visible_objects);
  a.boxes_tested += double(s.boxes_tested);
  tiles += double(s.tiles_tested);
  a.reads += double(s.reads);
  a.pixels_read += double(s.pixels_read);
  a.bytes_read += double(s.bytes_read);
  a.batches += double(s.batches);
  a.flushes += double(s.flushes);
  a.state_queries += double(s.state_queries);
  a.draw_batches += double(s.draw_batches);
  a.read_ms += s.read_seconds * 1e3;
  a.queries += double(s.queries);
  a.query_waits += double(s.query_waits);
  a.query_polls += double(s.query_polls);
  a.query_boxes += double(s.query_boxes);
  a.records_decided += double(s.records_decided);
  a.colliding_waits += double(s.colliding_waits);
  if (r.occluders >= 0) {
    addPresent(a.occluders, double(r.occluders));
    addPresent(a.occluder_tiles, double(s.occluder_tiles));
  }
  a.moved += double(r.moved);
  a.update_ms += r.update.seconds * 1e3;
  a.measure_ms += r.measure.seconds * 1e3;
  a.measure_counted += double(r.measure.counted);
  a.rebuilds += r.update.rebuilds;
  a.splits += r.update.splits;
  a.merges += r.update.merges;
  a.relocated += r.update.relocated;
  if (r.cpu) {
    a.cpu_ms += r.cpu->ms;
    a.cpu_wait_ms += r.cpu->wait_ms;
    a.cpu_worker_ms += r.cpu->worker_ms;
    a.cpu_objects += double(r.cpu->objects);
    a.cpu_triangles += double(r.cpu->triangles);
    a.cpu_tile_triangles += double(r.cpu->tile_triangles);
    a.cpu_tiles += double(r.cpu->tiles);
    a.cpu_fallbacks += double(r.cpu->fallbacks);
    a.cpu_unselected += double(r.cpu->unselected);
    a.cpu_moved += double(r.cpu->moved);
  }
  if (r.visible >= 0) {
    a.verified = true;
    a.visible += r.visible;
    a.missed += r.missed;
    a.artifacts += r.artifacts;
    a.missed_artifacts += r.missed_artifacts;
    a.frames_with_misses += r.missed > 0;
  }
}

}  // namespace

FrameAverages averageFrames(const std::vector<FrameRecord>& records) {
  FrameAverages a;
  a.frames = records.size();
  double tiles = 0;
  std::vector<double> times;
  for (const FrameRecord& r : records) {
    addFrame(r, a, tiles);
    times.push_back(r.ms);
  }
  a.tiles_per_box = a.boxes_tested > 0 ? tiles / a.boxes_tested : 0.0;
  a.median_ms = median(times);
  const double n = std::max<double>(1, double(records.size()));
  for (double* sum : {&a.ms,
                      &a.objects,
                      &a.triangles,
                      &a.draw_calls,
                      &a.boxes_tested,
                      &a.reads,
                      &a.pixels_read,
                      &a.bytes_read,
                      &a.batches,
                      &a.flushes,
                      &a.state_queries,
                      &a.draw_batches,
                      &a.read_ms,
                      &a.queries,
                      &a.query_waits,
                      &a.query_polls,
                      &a.query_boxes,
                      &a.records_decided,
                      &a.colliding_waits,
                      &a.moved,
                      &a.update_ms,
                      &a.measure_ms,
                      &a.measure_counted,
                      &a.cpu_ms,
                      &a.cpu_wait_ms,
                      &a.cpu_worker_ms,
                      &a.cpu_objects,
                      &a.cpu_triangles,
                      &a.cpu_tile_triangles,
                      &a.cpu_tiles,
                      &a.cpu_fallbacks,
                      &a.cpu_unselected,
                      &a.cpu_moved}) {
    *sum /= n;
  }
  if (a.cluster_objects) *a.cluster_objects /= n;
  if (a.occluders) *a.occluders /= n;
  if (a.occluder_tiles) *a.occluder_tiles /= n;
  return a;
}

nlohmann::json frameJson(const FrameRecord& r) {
  const FrameStats& s = r.stats;
  nlohmann::json j = {{"frame", r.frame},
                      {"ms", r.ms},
                      {"drawn_objects", s.objects_drawn},
                      {"drawn_triangles", r.triangles},
                      {"draw_calls", r.draw_calls},
                      {"boxes_tested", s.boxes_tested},
                      {"boxes_occluded", s.boxes_occluded},
                      {"tiles_tested", s.tiles_tested},
                      {"tiles_per_box", s.tilesPerBox()},
                      {"reads", s.reads},
                      {"read_pixels", s.pixels_read},
                      {"read_bytes", s.bytes_read},
                      {"queries", s.queries},
                      {"batches", s.batches},
                      {"flushes", s.flushes},
                      {"state_queries", s.state_queries},
                      {"draw_batches", s.draw_batches},
                      {"coherent_leaves", s.coherent_leaves},
                      {"visible_leaves", s.visible_leaves},
                      {"visible_kept", s.visible_kept},
                      {"read_ms", s.read_seconds * 1e3},
                      {"cull_ms", s.seconds * 1e3},
                      {"order_fallbacks", s.order_fallbacks},
                      {"invalid_boxes", s.invalid_boxes},
                      {"query_waits", s.query_waits},
                      {"query_polls", s.query_polls},
                      {"query_boxes", s.query_boxes},
                      {"multi_queries", s.multi_queries},
                      {"records_decided", s.records_decided},
                      {"boxes_untested", s.boxes_untested},
                      {"setting",
                       {{"method", toString(s.setting.method)},
                        {"lookahead", s.setting.lookahead},
                        {"coherence", s.setting.temporal_coherence},
                        {"probe", s.setting.probe},
                        {"visible_pixels", s.setting.approximation.visible_pixels},
                        {"full_fraction", s.setting.approximation.full_free_fraction},
                        {"row_stride", s.setting.approximation.row_stride}}}};
  if (r.objects_drawn >= 0) j["drawn_cluster_objects"] = r.objects_drawn;
  if (r.backfacing > 0) j["backfacing_clusters"] = r.backfacing;
  if (r.visible_objects >= 0) j["visible_cluster_objects"] = r.visible_objects;
  if (r.occluders >= 0) {
    j["occluders"] = r.occluders;
    j["occluder_tiles"] = s.occluder_tiles;
  }
  if (r.update.seconds > 0 || r.moved > 0) {  // a motion hierarchy (docs/MOTION.md)
    j["time"] = r.time;
    j["moved_objects"] = r.moved;
    j["update_ms"] = r.update.seconds * 1e3;
    j["measure_ms"] = r.measure.seconds * 1e3;
    j["measure_counted_nodes"] = r.measure.counted;
    j["measure_requests"] = r.measure.requests;
    j["rebuilds"] = r.update.rebuilds;
    j["splits"] = r.update.splits;
    j["merges"] = r.update.merges;
    j["relocated"] = r.update.relocated;
    j["colliding_waits"] = s.colliding_waits;
  }
  if (r.cpu) {
    j["cpu"] = {{"ms", r.cpu->ms},
                {"wait_ms", r.cpu->wait_ms},
                {"worker_ms", r.cpu->worker_ms},
                {"objects_set_up", r.cpu->objects},
                {"triangles_set_up", r.cpu->triangles},
                {"tile_triangles", r.cpu->tile_triangles},
                {"tiles", r.cpu->tiles},
                {"fallbacks", r.cpu->fallbacks},
                {"unselected", r.cpu->unselected},
                {"moved", r.cpu->moved}};
  }
  if (r.visible >= 0) {
    j["visible_objects"] = r.visible;
    j["missed_visible_objects"] = r.missed;
    j["depth_artifact_objects"] = r.artifacts;
    j["missed_depth_artifact_objects"] = r.missed_artifacts;
    if (!r.missed_ids.empty()) j["missed_ids"] = r.missed_ids;
  }
  return j;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

namespace {

// What the run was configured to do.
nlohmann::json settingsJson(const RunConfig& config, std::size_t frames) {
  return {{"method", config.method.name()},
          {"reader", config.reader},
          {"frames", frames},
          {"time_step", config.time_step},
          {"width", config.view.width},
          {"height", config.view.height},
          {"tile", config.culler.tile_size},
          {"lookahead", config.culler.lookahead == kUnlimitedLookahead
                            ? nlohmann::json("all")
                            : nlohmann::json(config.culler.lookahead)},
          {"temporal_coherence", config.culler.temporal_coherence},
          {"depth_format", toString(config.view.depth.format)},
          {"depth_convention", toString(config.view.depth.convention)},
          {"projection", config.view.orthographic ? "orthographic" : "perspective"},
          {"cull_back_faces", config.view.cull_back_faces},
          {"backface_clusters", config.backface_clusters},
          {"near", config.view.near_plane},
          {"far", config.view.far_plane}};
}

// The per-frame averages every method reports.
nlohmann::json averagesJson(const FrameAverages& a) {
  return {{"avg_frame_ms", a.ms},
          {"median_frame_ms", a.median_ms},
          {"avg_drawn_objects", a.objects},
          {"avg_drawn_triangles", a.triangles},
          {"avg_draw_calls", a.draw_calls},
          {"avg_read_pixels", a.pixels_read},
          {"avg_reads", a.reads},
          {"avg_queries", a.queries},
          {"avg_read_bytes", a.bytes_read},
          {"avg_batches", a.batches},
          {"avg_flushes", a.flushes},
          {"avg_state_queries", a.state_queries},
          {"avg_draw_batches", a.draw_batches},
          {"avg_query_waits", a.query_waits},
          {"avg_query_polls", a.query_polls},
          {"avg_records_decided", a.records_decided},
          {"avg_read_ms", a.read_ms},
          {"read_share", a.ms > 0 ? a.read_ms / a.ms : 0.0},
          {"avg_tiles_per_box", a.tiles_per_box}};
}

// The query schedule's settings and the hardware parameters it ran with.
nlohmann::json queriesJson(const RunConfig& config) {
  const QueryScheduleDesc& q = config.culler.queries;
  const HardwareParameters& h = q.hardware;
  return {
      {"schedule", toString(q.schedule)},
      {"shape", q.shape == QueryShape::Box ? "box" : "rect"},
      {"target", config.any_samples_passed ? "any_samples_passed_conservative" : "samples_passed"},
      {"chc_batch", q.chc_batch},
      {"chc_visible_interval", q.chc_visible_interval},
      {"stat_in_flight", q.stat_in_flight},
      {"stat_base_frames", q.stat_base_frames},
      {"hardware_s",
       {{"render_setup", h.render_setup},
        {"render_triangle", h.render_triangle},
        {"render_fragment", h.render_fragment},
        {"query_setup", h.query_setup},
        {"query_fragment", h.query_fragment},
        {"query_latency", h.query_latency},
        {"query_overhead", h.query_overhead},
        {"poll", h.poll}}}};
}

// The CPU occlusion buffer's settings and per-frame averages (--reader cpu).
nlohmann::json cpuJson(const RunConfig& config, const FrameAverages& a) {
  return {{"resolution", cpu::toString(config.cpu.resolution)},
          {"representation", cpu::toString(config.cpu.representation)},
          {"occluders", toString(config.cpu.occluders)},
          {"threads", config.cpu.threads},
          {"isa", cpu::toString(config.cpu.isa)},
          {"occluder_pixels", config.cpu.min_pixels_per_triangle},
          {"occluder_budget", config.cpu.triangle_budget},
          {"avg_ms", a.cpu_ms},
          {"avg_wait_ms", a.cpu_wait_ms},
          {"avg_worker_ms", a.cpu_worker_ms},
          {"avg_objects_set_up", a.cpu_objects},
          {"avg_triangles_set_up", a.cpu_triangles},
          {"avg_tile_triangles", a.cpu_tile_triangles},
          {"avg_tiles", a.cpu_tiles},
          {"avg_fallbacks", a.cpu_fallbacks},
          {"avg_unselected", a.cpu_unselected},
          {"avg_moved", a.cpu_moved}};
}

}  // namespace

nlohmann::json runSummary(const std::vector<FrameRecord>& records, const RunConfig& config,
                          bool per_frame) {
  const FrameAverages a = averageFrames(records);
  nlohmann::json j = settingsJson(config, records.size());
  j.update(averagesJson(a));
  if (a.cluster_objects) j["avg_drawn_cluster_objects"] = *a.cluster_objects;
  if (a.visible_cluster_objects) j["visible_cluster_objects"] = *a.visible_cluster_objects;
  if (a.occluders) j["avg_occluders"] = *a.occluders;
  if (a.occluder_tiles) j["avg_occluder_tiles"] = *a.occluder_tiles;
  if (config.method.method && methodInfo(*config.method.method).needs.queries) {
    j["queries"] = queriesJson(config);
  }
  if (config.reader == "cpu" && config.method.method) j["cpu"] = cpuJson(config, a);
  const GridApproximation& approximation = config.culler.approximation;
  // A budget approximates when its frames run over it (FrameStats::setting says when).
  j["conservative"] = approximation.exact() && config.culler.budget_ms == 0;
  if (config.culler.budget_ms > 0) j["budget_ms"] = config.culler.budget_ms;
  if (!approximation.exact()) {
    j["approximation"] = {{"visible_pixels", approximation.visible_pixels},
                          {"full_free_fraction", approximation.full_free_fraction},
                          {"row_stride", approximation.row_stride}};
  }
  if (a.verified) {
    j["visible_objects"] = a.visible;
    j["missed_visible_objects"] = a.missed;
    j["depth_artifact_objects"] = a.artifacts;
    j["missed_depth_artifact_objects"] = a.missed_artifacts;
  }
  if (per_frame) {
    nlohmann::json frames = nlohmann::json::array();
    for (const FrameRecord& r : records) frames.push_back(frameJson(r));
    j["per_frame"] = std::move(frames);
  }
  return j;
}

}  // namespace logrid::samples
