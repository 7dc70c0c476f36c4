// The skeleton every experiment of `logrid bench` runs on: bench itself (bench.cpp),
// --motion (bench_motion.cpp), --traversal (traversal_sweep.cpp) and --tradeoff
// (tradeoff.cpp). A driver declares its configurations as axes of variants (methods,
// readers, lookahead K, coherence, hierarchies, approximate settings ...), and the
// skeleton does the rest that every experiment does alike: the GL context and the
// machine's description, the report's header (Markdown and JSON), loading each scene
// (with its DDO octree when a configuration needs one), running the configurations
// interleaved on the same frames (interleaved.hpp) and adding up their frames
// (summary.hpp), the plots' paths and links, and writing the report with the exit code.
// The driver writes its own tables (writeTable() with its columns), JSON cells and plots.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cli/interleaved.hpp"
#include "cli/loaded_scene.hpp"
#include "cli/options.hpp"
#include "cli/plot.hpp"
#include "cli/summary.hpp"
#include "logrid/gl/context.hpp"

namespace logrid::samples {

// What bench's command line gives every experiment.
struct ExperimentOptions {
  WalkOptions walk;  // what every configuration shares: frames, view, reader, depth ...
  std::vector<std::string> scenes;
  std::vector<std::string> sizes;
  double forest_scale = 0;  // 0: walk.scale
  double city_scale = 0;
  std::size_t repeat = 3;
  std::size_t warmup = 2;  // frames each configuration renders first, untimed
  bool verify = true;      // every frame of the first repetition against the object-ID oracle
  std::string markdown;    // report files to write ("" for none); the report goes to stdout
  std::string json;
  std::string plots;  // folder for the plots
};

// One configuration of an experiment: its label, and what it sets in the options of the
// cell (scene, size and the command's options) it runs in.
struct Variant {
  std::string label;
  std::function<void(WalkOptions&)> apply;
};
using Axis = std::vector<Variant>;

// Every combination of one variant from each axis, the first axis varying slowest (as
// nested loops over the axes would run); labels joined by spaces, empty ones left out.
std::vector<Variant> combine(const std::vector<Axis>& axes);

// A configuration's outcome in one cell.
struct Measured {
  std::string label;
  ConfigResult result;   // its configuration, frame times, the first repetition's records
  FrameAverages frames;  // averageFrames(result.records)
};

// A configuration's method without its traversal settings (":K", ":tc"), e.g. "log-state"
// for log-state:32:tc: the family its plots group it in.
std::string methodFamily(const RunConfig& config);

// Small multiples: the configurations' series (those `series` gives one) in panels, one
// per method family with several configurations and one for the families of a single
// configuration ("other methods"), with `floor` (e.g. the oracle as a band) in each.
std::vector<PlotPanel> familyPanels(
    const std::vector<Measured>& measured,
    const std::function<std::optional<PlotSeries>(const Measured&)>& series,
    const std::optional<PlotSeries>& floor = std::nullopt);

class Experiment {
 public:
  // The report opens with "# title", the machine, the date, the command line and `intro`
  // (Markdown); its JSON with command, machine, date and repeat. `name` ("bench
  // --traversal") starts the messages of bad arguments. Throws logrid::Error for empty
  // scene or size lists, and when the GL context cannot be made.
  Experiment(const ExperimentOptions& options, const std::string& name, const std::string& title,
             const std::string& intro);
  ~Experiment();

  const ExperimentOptions& options() const { return options_; }
  std::ostringstream& md() { return md_; }
  nlohmann::json& report() { return report_; }

  // The options of one scene: walk's, with its name and (forest_scale, city_scale) scale.
  WalkOptions sceneOptions(const std::string& scene) const;
  // The scene the options name, uploaded, with the DDO octree when one of the variants'
  // methods needs it.
  LoadedScene load(const WalkOptions& scene_options, const std::vector<Variant>& variants) const;
  // The variants on the cell's frames: each applied to `cell` (with options().verify),
  // all run interleaved with options().repeat and options().warmup. Throws
  // logrid::Error for a variant runConfig() refuses, before anything runs.
  std::vector<Measured> run(const LoadedScene& scene, const WalkOptions& cell,
                            const std::vector<Variant>& variants,
                            const std::string& progress_label) const;

  // Plots: the path stem of a plot in the plots folder ("" when no plots were asked for),
  // and a Markdown image of it ("" unless both plots and a Markdown file are written).
  std::string plotStem(const std::string& name) const;
  std::string plotImage(const std::string& alt, const std::string& name) const;

  // Prints the Markdown, writes the report files, and returns the exit code: 0, or 1
  // after saying `failure` on stderr when it is not empty.
  int finish(const std::string& failure);

 private:
  ExperimentOptions options_;
  std::unique_ptr<gl::Context> context_;
  std::ostringstream md_;
  nlohmann::json report_;
};

}  // namespace logrid::samples
