// What the logrid commands share: the options of a walkthrough, getting the scene
// (procedural or from a file) ready, machine information, and progress output.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/frame_runner.hpp"
#include "logrid/gl/context.hpp"
#include "scene/ddo_scene.hpp"
#include "scene/generators.hpp"
#include "scene/prepare.hpp"

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
  std::string cpu_resolution = "full";  // --reader cpu: full, half or quarter
  std::string occluders = "mesh";       // --reader cpu: mesh or model
  std::uint32_t cpu_threads = 0;        // --reader cpu: worker threads
  std::string cpu_isa = "auto";         // --reader cpu: auto, scalar, sse4.1 or avx2
  std::string lookahead = "1";          // a count, or "all"
  bool coherence = false;
  std::string depth_format = "32f";
  std::string depth_convention = "standard";
  std::uint32_t samples = 0;
  double near_plane = 0;  // 0: the scene's
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
  GridApproximation approximation;   // off by default
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

// Whether a method name needs the DDO octree.
bool needsDdo(const std::string& method);

// Adds the options every walkthrough command has (--scene ... --platform).
void addSceneOptions(CLI::App& app, WalkOptions& o);
// The same without --scene (for commands that take several scenes).
void addWalkthroughOptions(CLI::App& app, WalkOptions& o);
void addViewOptions(CLI::App& app, WalkOptions& o);

// Splits a comma-separated list ("forest,city"), dropping empty items.
std::vector<std::string> splitList(const std::string& text);

// Parses "WxH"; throws logrid::Error(InvalidArgument) naming the text.
std::pair<std::uint32_t, std::uint32_t> parseSize(const std::string& text);
DepthFormat parseDepthFormat(const std::string& text);
DepthConvention parseDepthConvention(const std::string& text);
TreeParts parseTreeParts(const std::string& text);
// "1", "16", ... or "all" (kUnlimitedLookahead).
std::uint32_t parseLookahead(const std::string& text);

// A scene ready to draw: prepared, uploaded, with how long each step took.
struct LoadedScene {
  PreparedScene prepared;
  std::unique_ptr<gl::MeshRenderer> renderer;
  std::optional<DdoScene> ddo;               // when a method needs it (then also prepared.ddo)
  double generate_ms = 0;                    // generating or loading
  std::uint64_t peak_rss_bytes = 0;          // after uploading to GL
  std::uint64_t prepare_peak_rss_bytes = 0;  // after generating and preparing, before GL
  nlohmann::json describe() const;
};

// The options of `base` for one scene of a multi-scene command: its name, and
// forest_scale / city_scale for the procedural scenes when > 0.
WalkOptions optionsForScene(const WalkOptions& base, const std::string& scene, double forest_scale,
                            double city_scale);

// Creates (or loads) the scene named by the options and, with `upload`, uploads it
// (needs a context then). With `with_ddo`, also builds or loads its DDO octree.
LoadedScene loadScene(const WalkOptions& o, bool upload = true, bool with_ddo = false);

// The DDO options the walkthrough options ask for (the file resolved).
DdoOptions ddoOptions(const WalkOptions& o);
nlohmann::json describeDdo(const DdoScene& d);

// The run configuration from the options (method, view, tile, reader, depth ...).
RunConfig runConfig(const WalkOptions& o, const PreparedScene& scene);

gl::ContextDesc contextDesc(const WalkOptions& o);

// The command line as typed (quoted where needed), recorded by main() for reports.
void setCommandLine(int argc, char** argv);
const std::string& commandLine();

// GL renderer, cores, CPU model, LP_NUM_THREADS.
nlohmann::json machineInfo(const gl::Context& context);
std::string machineLine(const nlohmann::json& machine);

// Progress on stderr: rewrites one line on a terminal, prints every ~10% otherwise.
class Progress {
 public:
  explicit Progress(std::string label, std::size_t total);
  void update(std::size_t done, double ms_per_frame);
  void finish();

 private:
  std::string label_;
  std::size_t total_;
  bool tty_;
  std::size_t last_percent_ = 0;
};

// Reads the peak resident set size of this process (bytes), 0 if unknown.
std::uint64_t peakRssBytes();

// Writes JSON to a file; throws logrid::Error(Environment) naming the path.
void writeJson(const std::string& path, const nlohmann::json& json);

}  // namespace logrid::samples
