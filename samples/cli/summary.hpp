// Summaries of runs: the frames of a run added up once (FrameAverages), and as JSON (the
// contract other tools read, see README "logrid walk").
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <vector>

#include "cli/frame_runner.hpp"

namespace logrid::samples {

// A run's frames added up: per-frame averages of what each frame counted (sums divided by
// the number of frames), sums of the motion hierarchy's events and of the object-ID
// oracle's counts. Every summary and table of a run reads its figures from here.
struct FrameAverages {
  std::size_t frames = 0;
  double ms = 0;  // frame time, average
  double median_ms = 0;
  // FrameStats and FrameRecord, averages per frame.
  double objects = 0;  // objects drawn (clusters, in a clustered scene)
  double triangles = 0;
  double draw_calls = 0;
  // Clustered scenes (FrameRecord::objects_drawn, visible_objects): objects a drawn
  // cluster belongs to, an average; objects a visible cluster belongs to, a sum.
  std::optional<double> cluster_objects;
  std::optional<std::int64_t> visible_cluster_objects;
  double boxes_tested = 0;
  double tiles_per_box = 0;  // tiles tested / boxes tested, over all frames
  double reads = 0;
  double pixels_read = 0;
  double bytes_read = 0;
  double batches = 0;
  double flushes = 0;
  double state_queries = 0;  // the sources' GL state queries (FrameStats::state_queries)
  double draw_batches = 0;   // batches handed out (FrameStats::draw_batches)
  double read_ms = 0;
  double queries = 0;
  double query_waits = 0;
  double query_polls = 0;
  double query_boxes = 0;
  double records_decided = 0;
  double colliding_waits = 0;
  std::optional<double> occluders;       // DDO methods: occluders per frame
  std::optional<double> occluder_tiles;  // ddo+log: tiles recorded hidden by them per frame
  // The motion hierarchy (frame_runner.hpp): averages, and sums of its events.
  double moved = 0;
  double update_ms = 0;
  double measure_ms = 0;
  double measure_counted = 0;  // the ternary tree's additional queries
  std::uint64_t rebuilds = 0, splits = 0, merges = 0, relocated = 0;
  // --reader cpu: averages of CpuFrameStats.
  double cpu_ms = 0, cpu_wait_ms = 0, cpu_worker_ms = 0, cpu_objects = 0, cpu_triangles = 0,
         cpu_tile_triangles = 0, cpu_tiles = 0, cpu_fallbacks = 0, cpu_unselected = 0,
         cpu_moved = 0;  // moving objects handed over with their transform
  // The object-ID oracle (frames checked with verify), sums.
  bool verified = false;
  std::int64_t visible = 0;
  std::int64_t missed = 0;
  std::int64_t artifacts = 0;
  std::int64_t missed_artifacts = 0;
  std::size_t frames_with_misses = 0;
};

FrameAverages averageFrames(const std::vector<FrameRecord>& records);

nlohmann::json frameJson(const FrameRecord& r);

// The summary of one run: averages over `records` (all given frames), sums of the
// oracle counts, and the per-frame array when `per_frame`.
nlohmann::json runSummary(const std::vector<FrameRecord>& records, const RunConfig& config,
                          bool per_frame);

double median(std::vector<double> values);

}  // namespace logrid::samples
