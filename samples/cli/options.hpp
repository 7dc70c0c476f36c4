// The options every walkthrough command shares (walk, bench, tune, ddo, view): what they
// hold (WalkOptions) and how they are added to a command. Numeric options go through
// addNumber() (option_checks.hpp), which states and checks each one's range.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

#include "logrid/grid.hpp"

namespace logrid::samples {

struct WalkOptions {
  std::string scene;
  double scale = 1.0;
  std::uint64_t seed = 1;
  std::string path_file;
  std::size_t frames = 100;
  double time_step = 0;  // > 0: path time between frames (RunConfig::time_step)
  std::string method = "log-state";
  std::string size = "640x480";
  std::uint32_t tile = 32;
  std::string reader = "readpixels";
  std::string costs;  // a costs file of `logrid calibrate --costs` (CullerDesc::costs)
  std::string cpu_resolution = "full";   // --reader cpu: full, half or quarter
  std::string cpu_buffer = "per-pixel";  // --reader cpu: per-pixel or masked
  std::string occluders = "mesh";        // --reader cpu: mesh or model
  double occluder_pixels = 0;            // --reader cpu: min screen pixels per occluder triangle
  std::uint32_t occluder_budget = 0;     // --reader cpu: occluder triangles per frame (0: all)
  std::uint32_t cpu_threads = 0;         // --reader cpu: worker threads
  std::string cpu_isa = "auto";          // --reader cpu: auto, scalar, sse4.1 or avx2
  std::string lookahead = "1";           // a count, or "all"
  bool coherence = false;
  std::string depth_format = "32f";
  std::string depth_convention = "standard";
  std::uint32_t samples = 0;
  bool cull_back_faces = false;    // the renderer culls back faces (ViewSettings)
  bool backface_clusters = false;  // and clusters facing away are not drawn (RunConfig)
  double near_plane = 0;           // 0: the scene's
  double far_plane = 0;
  double fov = 60;
  bool ortho = false;
  bool verify = false;
  std::string json;
  std::string images;
  bool overlay = false;
  std::string platform = "auto";
  int lp_threads = -1;     // >= 0: LP_NUM_THREADS for llvmpipe (docs/PLATFORM.md); -1: leave it
  std::uint32_t leaf = 0;  // 0: the scene's default
  std::string tree_parts = "whole";  // forest: whole, trunk-crown or tiers
  std::uint32_t cluster = 0;         // triangles per cluster (scene/clusters.hpp); 0: whole objects
  std::string cluster_method = "grow";  // grow or scan (ClusterMethod)
  GridApproximation approximation;      // off by default
  double budget_ms = 0;                 // CullerDesc::budget_ms (0: none)
  // Motion (motion.hpp, movers.hpp).
  std::uint32_t movers = 0;        // moving objects added to the scene
  std::string motion_file;         // a scene from a file: its meshes' paths
  std::string hierarchy = "auto";  // RunConfig::hierarchy
  bool colliding = false;          // CullerDesc::detect_colliding
  // The query methods (hwq, chc, stat, nohc, log+hwq), CullerDesc::queries.
  std::string query_schedule = "stat";  // log+hwq's schedule of the undecided boxes
  std::string query_shape = "box";      // box or rect
  bool any_samples = false;             // GL_ANY_SAMPLES_PASSED_CONSERVATIVE queries
  std::uint32_t chc_batch = 50;
  std::uint32_t chc_interval = 5;
  std::uint32_t stat_in_flight = 20;
  std::uint32_t stat_base = 20;
  // Directional discretized occluders (methods ddo and ddo+log, scene/ddo_scene.hpp).
  std::uint32_t ddo_regions = 64;
  std::uint32_t ddo_leaf = 2048;
  std::string ddo_file = "auto";  // auto: FILE.ddo next to a model file, none for the
                                  // procedural scenes; none: never; else a path
  bool ddo_rebuild = false;
  std::uint32_t ddo_threads = 0;
};

// Adds the options every walkthrough command has (--scene ... --platform).
void addSceneOptions(CLI::App& app, WalkOptions& o);
// The same without --scene (for commands that take several scenes).
void addWalkthroughOptions(CLI::App& app, WalkOptions& o);
// The view, reader, depth, projection and approximation options (--tile ... --stat-base).
void addViewOptions(CLI::App& app, WalkOptions& o);
// --size, a viewport WIDTHxHEIGHT ("viewport" as `help` says "viewport WIDTHxHEIGHT, each
// side in range [1, 32768]").
CLI::Option* addSizeOption(CLI::App& app, std::string& size, const std::string& help);
// --lookahead, a count of boxes or "all".
CLI::Option* addLookaheadOption(CLI::App& app, std::string& lookahead, const std::string& help);
// --lp-threads, llvmpipe's LP_NUM_THREADS (WalkOptions::lp_threads).
CLI::Option* addLlvmpipeThreadsOption(CLI::App& app, int& threads, const std::string& help);

}  // namespace logrid::samples
