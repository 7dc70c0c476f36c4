#include "cli/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "logrid/error.hpp"

namespace logrid::samples {

nlohmann::json frameJson(const FrameRecord& r) {
  const FrameStats& s = r.stats;
  nlohmann::json j = {{"frame", r.frame},
                      {"ms", r.ms},
                      {"drawn_objects", s.objects_drawn},
                      {"drawn_triangles", r.triangles},
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
                      {"coherent_leaves", s.coherent_leaves},
                      {"read_ms", s.read_seconds * 1e3},
                      {"cull_ms", s.seconds * 1e3},
                      {"order_fallbacks", s.order_fallbacks},
                      {"invalid_boxes", s.invalid_boxes},
                      {"query_waits", s.query_waits},
                      {"query_polls", s.query_polls},
                      {"query_boxes", s.query_boxes},
                      {"multi_queries", s.multi_queries},
                      {"records_decided", s.records_decided}};
  if (r.occluders >= 0) j["occluders"] = r.occluders;
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
                {"fallbacks", r.cpu->fallbacks}};
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

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw Error(ErrorCode::Environment, "cannot write '" + path + "' (check the folder)");
}

std::string formatFixed(double value, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  return buf;
}

std::string formatRatio(double a, double b, const char* suffix) {
  return b > 0 ? formatFixed(a / b, 2) + suffix : "–";
}

std::string linkFrom(const std::string& document, const std::string& target) {
  namespace fs = std::filesystem;
  return fs::relative(fs::absolute(target), fs::absolute(document).parent_path()).string();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

nlohmann::json runSummary(const std::vector<FrameRecord>& records, const RunConfig& config,
                          bool per_frame) {
  double ms = 0, objects = 0, triangles = 0, pixels = 0, tiles = 0, boxes = 0, read_ms = 0,
         reads = 0, queries = 0, bytes = 0, batches = 0, flushes = 0, waits = 0, polls = 0,
         decided = 0, occluders = 0;
  bool with_occluders = false;
  CpuFrameStats cpu_sum;  // sums
  std::int64_t visible = 0, missed = 0, artifacts = 0, missed_artifacts = 0;
  bool verified = false;
  std::vector<double> times;
  for (const FrameRecord& r : records) {
    ms += r.ms;
    times.push_back(r.ms);
    objects += double(r.stats.objects_drawn);
    triangles += double(r.triangles);
    pixels += double(r.stats.pixels_read);
    tiles += double(r.stats.tiles_tested);
    boxes += double(r.stats.boxes_tested);
    read_ms += r.stats.read_seconds * 1e3;
    reads += double(r.stats.reads);
    queries += double(r.stats.queries);
    bytes += double(r.stats.bytes_read);
    batches += double(r.stats.batches);
    flushes += double(r.stats.flushes);
    if (r.occluders >= 0) with_occluders = true, occluders += double(r.occluders);
    waits += double(r.stats.query_waits);
    polls += double(r.stats.query_polls);
    decided += double(r.stats.records_decided);
    if (r.cpu) {
      cpu_sum.ms += r.cpu->ms;
      cpu_sum.wait_ms += r.cpu->wait_ms;
      cpu_sum.worker_ms += r.cpu->worker_ms;
      cpu_sum.objects += r.cpu->objects;
      cpu_sum.triangles += r.cpu->triangles;
      cpu_sum.tile_triangles += r.cpu->tile_triangles;
      cpu_sum.tiles += r.cpu->tiles;
      cpu_sum.fallbacks += r.cpu->fallbacks;
    }
    if (r.visible >= 0) {
      verified = true;
      visible += r.visible;
      missed += r.missed;
      artifacts += r.artifacts;
      missed_artifacts += r.missed_artifacts;
    }
  }
  const double n = std::max<double>(1, double(records.size()));
  nlohmann::json j = {{"method", config.method.name()},
                      {"reader", config.reader},
                      {"frames", records.size()},
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
                      {"near", config.view.near_plane},
                      {"far", config.view.far_plane},
                      {"avg_frame_ms", ms / n},
                      {"median_frame_ms", median(times)},
                      {"avg_drawn_objects", objects / n},
                      {"avg_drawn_triangles", triangles / n},
                      {"avg_read_pixels", pixels / n},
                      {"avg_reads", reads / n},
                      {"avg_queries", queries / n},
                      {"avg_read_bytes", bytes / n},
                      {"avg_batches", batches / n},
                      {"avg_flushes", flushes / n},
                      {"avg_query_waits", waits / n},
                      {"avg_query_polls", polls / n},
                      {"avg_records_decided", decided / n},
                      {"avg_read_ms", read_ms / n},
                      {"read_share", ms > 0 ? read_ms / ms : 0.0},
                      {"avg_tiles_per_box", boxes > 0 ? tiles / boxes : 0.0}};
  if (with_occluders) j["avg_occluders"] = occluders / n;
  if (config.method.method && methodInfo(*config.method.method).needs.queries) {
    const QueryScheduleDesc& q = config.culler.queries;
    const HardwareParameters& h = q.hardware;
    j["queries"] = {{"schedule", toString(q.schedule)},
                    {"shape", q.shape == QueryShape::Box ? "box" : "rect"},
                    {"target", config.any_samples_passed ? "any_samples_passed_conservative"
                                                         : "samples_passed"},
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
  if (config.reader == "cpu" && config.method.method) {
    j["cpu"] = {{"resolution", cpu::toString(config.cpu.resolution)},
                {"occluders", toString(config.cpu.occluders)},
                {"threads", config.cpu.threads},
                {"isa", cpu::toString(config.cpu.isa)},
                {"avg_ms", cpu_sum.ms / n},
                {"avg_wait_ms", cpu_sum.wait_ms / n},
                {"avg_worker_ms", cpu_sum.worker_ms / n},
                {"avg_objects_set_up", double(cpu_sum.objects) / n},
                {"avg_triangles_set_up", double(cpu_sum.triangles) / n},
                {"avg_tile_triangles", double(cpu_sum.tile_triangles) / n},
                {"avg_tiles", double(cpu_sum.tiles) / n},
                {"avg_fallbacks", double(cpu_sum.fallbacks) / n}};
  }
  const GridApproximation& a = config.culler.approximation;
  j["conservative"] = a.exact();
  if (!a.exact()) {
    j["approximation"] = {{"visible_pixels", a.visible_pixels},
                          {"full_free_fraction", a.full_free_fraction},
                          {"row_stride", a.row_stride}};
  }
  if (verified) {
    j["visible_objects"] = visible;
    j["missed_visible_objects"] = missed;
    j["depth_artifact_objects"] = artifacts;
    j["missed_depth_artifact_objects"] = missed_artifacts;
  }
  if (per_frame) {
    nlohmann::json frames = nlohmann::json::array();
    for (const FrameRecord& r : records) frames.push_back(frameJson(r));
    j["per_frame"] = std::move(frames);
  }
  return j;
}

std::string framesAlong(std::size_t frames, double time_step) {
  if (time_step > 0) {
    return std::to_string(frames) + " frames " + formatFixed(time_step, 3) +
           " s of path time apart from the walkthrough's start";
  }
  return std::to_string(frames) + " frames along the walkthrough";
}

std::string grouped(double v) {
  std::string digits = std::to_string(static_cast<long long>(std::llround(v)));
  for (int i = int(digits.size()) - 3; i > 0 && digits[std::size_t(i) - 1] != '-'; i -= 3) {
    digits.insert(std::size_t(i), ",");
  }
  return digits;
}

}  // namespace logrid::samples
