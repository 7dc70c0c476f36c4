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
                      {"invalid_boxes", s.invalid_boxes}};
  if (r.occluders >= 0) j["occluders"] = r.occluders;
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
         reads = 0, queries = 0, bytes = 0, batches = 0, flushes = 0, occluders = 0;
  bool with_occluders = false;
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
                      {"avg_read_ms", read_ms / n},
                      {"read_share", ms > 0 ? read_ms / ms : 0.0},
                      {"avg_tiles_per_box", boxes > 0 ? tiles / boxes : 0.0}};
  if (with_occluders) j["avg_occluders"] = occluders / n;
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

std::string grouped(double v) {
  std::string digits = std::to_string(static_cast<long long>(std::llround(v)));
  for (int i = int(digits.size()) - 3; i > 0 && digits[std::size_t(i) - 1] != '-'; i -= 3) {
    digits.insert(std::size_t(i), ",");
  }
  return digits;
}

}  // namespace logrid::samples
