// logrid tune: sweeps the tile size on a scene and path (procedural or a user's file),
// every size on the same frames (interleaved), and recommends the fastest; with --auto,
// the whole configuration space in stages (tune_auto.hpp).
#include <charconv>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/interleaved.hpp"
#include "cli/loaded_scene.hpp"
#include "cli/machine.hpp"
#include "cli/option_checks.hpp"
#include "cli/plot.hpp"
#include "cli/report.hpp"
#include "cli/summary.hpp"
#include "cli/tune_auto.hpp"
#include "cli/values.hpp"
#include "logrid/camera.hpp"
#include "logrid/error.hpp"

namespace logrid::samples {
namespace {

struct TuneOptions {
  WalkOptions walk;
  std::string tiles = "4,8,16,32,64,128";
  std::size_t repeat = 3;
  std::string json;
  std::string plot;  // PNG path stem
  bool automatic = false;   // --auto: tune_auto.hpp
  std::string write_config;  // --auto: the configuration file written
};

// The values --tiles takes.
NumberRange<std::uint32_t> tileRange() { return closed(1u, kMaxViewportSide); }

// "4,8,16" -> {4, 8, 16}; throws logrid::Error(InvalidArgument) naming a bad item.
std::vector<std::uint32_t> parseTiles(const std::string& text) {
  std::vector<std::uint32_t> tiles;
  for (const std::string& item : splitList(text)) {
    const std::string problem = numberProblem(item, tileRange());
    if (!problem.empty()) throw Error(ErrorCode::InvalidArgument, "tune: --tiles: " + problem);
    std::uint32_t tile = 0;
    parseNumber(item, tile);
    tiles.push_back(tile);
  }
  if (tiles.empty()) throw Error(ErrorCode::InvalidArgument, "tune: --tiles needs a size");
  return tiles;
}

int runTune(const TuneOptions& o) {
  if (o.automatic) return runTuneAuto({o.walk, o.repeat, o.json, o.write_config});
  const std::vector<std::uint32_t> tiles = parseTiles(o.tiles);
  gl::Context context(contextDesc(o.walk));
  LoadedScene scene = loadScene(o.walk);
  std::vector<RunConfig> configs;
  for (std::uint32_t tile : tiles) {
    WalkOptions t = o.walk;
    t.tile = tile;
    configs.push_back(runConfig(t, scene.prepared));
  }
  const std::vector<ConfigResult> results =
      runInterleaved(scene.prepared, *scene.renderer, configs, o.repeat,
                     "tune " + scene.prepared.name + " " + o.walk.method);

  std::size_t best = 0;
  for (std::size_t i = 1; i < results.size(); ++i) {
    if (results[i].avg_ms() < results[best].avg_ms()) best = i;
  }
  std::printf("%s, %s, %s, %s reader, %zu frames x %zu repetitions\n", scene.prepared.name.c_str(),
              o.walk.method.c_str(), o.walk.size.c_str(), o.walk.reader.c_str(),
              configs.front().frames, o.repeat);
  std::printf("%6s %10s %8s %14s %10s %8s\n", "tile", "ms/frame", "spread", "pixels read",
              "tiles/box", "missed");
  nlohmann::json report = scene.describe();
  report["command"] = commandLine();
  report["machine"] = machineInfo(context);
  report["sizes"] = nlohmann::json::array();
  PlotSeries ms{"ms/frame", {}, {}, {}, {}}, px{"pixels read", {}, {}, {}, {}};
  bool missed = false;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const ConfigResult& r = results[i];
    nlohmann::json s = runSummary(r.records, r.config, false);
    s["avg_frame_ms"] = r.avg_ms();
    s["spread"] = r.spread();
    const std::int64_t miss = s.value("missed_visible_objects", std::int64_t{-1});
    missed |= miss > 0;
    std::printf("%6u %10.2f %7.0f%% %14.0f %10.2f %8s%s\n", r.config.culler.tile_size, r.avg_ms(),
                100 * r.spread(), s["avg_read_pixels"].get<double>(),
                s["avg_tiles_per_box"].get<double>(),
                miss >= 0 ? std::to_string(miss).c_str() : "–", i == best ? "   <- best" : "");
    ms.x.push_back(r.config.culler.tile_size);
    ms.y.push_back(r.avg_ms());
    px.x.push_back(r.config.culler.tile_size);
    px.y.push_back(s["avg_read_pixels"].get<double>());
    report["sizes"].push_back(std::move(s));
  }
  report["recommended_tile"] = results[best].config.culler.tile_size;
  std::printf("recommended: --tile %u (%.2f ms/frame)\n", results[best].config.culler.tile_size,
              results[best].avg_ms());
  if (!o.plot.empty()) {
    PlotAxes axes{"tile size (pixels)", "", PlotScale::Auto, true, {}, false};
    for (std::uint32_t tile : tiles) axes.xtics.push_back({double(tile), std::to_string(tile)});
    plotPanels(o.plot,
               scene.prepared.name + " " + o.walk.method + " " + o.walk.size + ": tile size sweep",
               axes, {{"frame time (ms)", {ms}}, {"depth pixels read per frame", {px}}});
  }
  if (!o.json.empty()) writeJson(o.json, report);
  if (missed) {
    std::fprintf(stderr, "tune: a conservative run missed visible objects: a bug\n");
    return 1;
  }
  return 0;
}

}  // namespace

void addTuneCommand(CLI::App& app) {
  auto o = std::make_shared<TuneOptions>();
  o->walk.frames = 30;
  CLI::App* tune = app.add_subcommand(
      "tune", "sweep tile sizes on a scene and recommend one, or with --auto the whole setting");
  addSceneOptions(*tune, o->walk);
  std::string gridded;
  for (const MethodInfo& m : methodTable()) {
    if (m.grid) gridded += std::string(gridded.empty() ? "" : ", ") + m.name;
  }
  tune->add_option("--method", o->walk.method,
                   "the method whose tile size is swept, one with a grid: " + gridded);
  addSizeOption(*tune, o->walk.size, "viewport");
  addViewOptions(*tune, o->walk);
  tune->add_option("--tiles", o->tiles,
                   "comma-separated tile sizes to try (default 4,8,16,32,64,128); each in "
                   "range " +
                       tileRange().text())
      ->check(numberListCheck(tileRange()));
  addNumber(*tune, "--repeat", o->repeat, closed<std::size_t>(1, kMaxRepeats),
            "interleaved repetitions; medians are reported");
  tune->add_flag("--verify", o->walk.verify, "check the first repetition against the oracle");
  tune->add_option("--json", o->json, "write the sweep as JSON");
  tune->add_option("--plot", o->plot, "write STEM.png (and .dat/.gp) with gnuplot");
  CLI::Option* automatic = tune->add_flag(
      "--auto", o->automatic,
      "sweep method, lookahead, coherence, tile size, depth reader and box granularity in "
      "stages on the same frames, and say which parts the scene needs");
  automatic->excludes("--method")->excludes("--tiles")->excludes("--plot");
  tune->add_option("--write-config", o->write_config,
                   "with --auto: write the fastest setting as a configuration file (walk, bench "
                   "and view take it with --config)")
      ->needs(automatic);
  tune->final_callback([o] { throw CLI::RuntimeError(runTune(*o)); });
}

}  // namespace logrid::samples
