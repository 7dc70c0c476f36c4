// logrid walk: one method along a walkthrough, with an optional object-ID check,
// images and overlays, and a JSON summary.
#include <cstdio>
#include <memory>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/config_option.hpp"
#include "cli/loaded_scene.hpp"
#include "cli/machine.hpp"
#include "cli/progress.hpp"
#include "cli/report.hpp"
#include "cli/summary.hpp"

namespace logrid::samples {
namespace {

int runWalk(const WalkOptions& o) {
  gl::Context context(contextDesc(o));
  LoadedScene scene = loadScene(o, true, needsDdo(o.method));
  const RunConfig config = runConfig(o, scene.prepared);
  FrameRunner runner(scene.prepared, *scene.renderer, config);
  Progress progress("walk " + scene.prepared.name + " " + config.method.name(), config.frames);
  std::vector<FrameRecord> records;
  double total_ms = 0;
  for (std::size_t f = 0; f < config.frames; ++f) {
    records.push_back(runner.renderFrame(f));
    total_ms += records.back().ms;
    progress.update(f + 1, total_ms / double(f + 1));
  }
  progress.finish();

  nlohmann::json summary = scene.describe();
  summary.update(runSummary(records, config, true));
  summary["machine"] = machineInfo(context);
  std::printf(
      "%s %s %ux%u tile %u: %.2f ms/frame, %.0f objects, %.0f triangles, %.0f pixels read, "
      "%.2f tiles/box",
      scene.prepared.name.c_str(), config.method.name().c_str(), config.view.width,
      config.view.height, config.culler.tile_size, summary["avg_frame_ms"].get<double>(),
      summary["avg_drawn_objects"].get<double>(), summary["avg_drawn_triangles"].get<double>(),
      summary["avg_read_pixels"].get<double>(), summary["avg_tiles_per_box"].get<double>());
  if (config.method.method && methodInfo(*config.method.method).needs.queries) {
    std::printf(", %.1f queries (%.1f waited for), %.1f flushes",
                summary["avg_queries"].get<double>(), summary["avg_query_waits"].get<double>(),
                summary["avg_flushes"].get<double>());
  }
  std::printf(", %.1f reads in %.1f batches, %.1f GL state queries",
              summary["avg_reads"].get<double>(), summary["avg_draw_batches"].get<double>(),
              summary["avg_state_queries"].get<double>());
  if (summary.contains("visible_objects")) {
    std::printf(", %lld visible, %lld missed",
                (long long)summary["visible_objects"].get<std::int64_t>(),
                (long long)summary["missed_visible_objects"].get<std::int64_t>());
    const auto artifacts = summary["depth_artifact_objects"].get<std::int64_t>();
    if (artifacts > 0) {
      std::printf(" (and %lld shown only by depth-extrapolated fragments, %lld of them not drawn)",
                  (long long)artifacts,
                  (long long)summary["missed_depth_artifact_objects"].get<std::int64_t>());
    }
  }
  std::printf("\n");
  if (summary.contains("cpu")) {
    const nlohmann::json& c = summary["cpu"];
    std::printf(
        "cpu buffer (%s, %s occluders, %u threads, %s): %.3f ms/frame in the buffer (%.3f waiting, "
        "workers %.3f), %.0f triangles set up, %.0f triangle-tiles rasterised in %.0f tiles, "
        "%.1f flushes\n",
        c["resolution"].get<std::string>().c_str(), c["occluders"].get<std::string>().c_str(),
        c["threads"].get<unsigned>(), c["isa"].get<std::string>().c_str(),
        c["avg_ms"].get<double>(), c["avg_wait_ms"].get<double>(), c["avg_worker_ms"].get<double>(),
        c["avg_triangles_set_up"].get<double>(), c["avg_tile_triangles"].get<double>(),
        c["avg_tiles"].get<double>(), summary["avg_flushes"].get<double>());
  }
  if (!o.json.empty()) writeJson(o.json, summary);

  if (summary.value("missed_visible_objects", std::int64_t{0}) > 0) {
    for (const FrameRecord& r : records) {
      if (r.missed > 0) {
        std::fprintf(stderr, "walk: frame %zu: %lld visible objects were not drawn (first: %u)\n",
                     r.frame, (long long)r.missed, r.missed_ids.front());
      }
    }
    if (!summary["conservative"].get<bool>()) {
      // What an approximate setting pays for its speed (docs/TRADEOFF.md), not a bug.
      std::fprintf(stderr, "walk: %s with approximate settings missed %lld visible objects\n",
                   config.method.name().c_str(),
                   (long long)summary["missed_visible_objects"].get<std::int64_t>());
      return 0;
    }
    std::fprintf(stderr,
                 "walk: %s missed visible objects: a conservative method must never do "
                 "that; please report it with the command line\n",
                 config.method.name().c_str());
    return 1;
  }
  return 0;
}

}  // namespace

void addWalkCommand(CLI::App& app) {
  auto options = std::make_shared<WalkOptions>();
  CLI::App* walk = app.add_subcommand("walk", "render a walkthrough with one culling method");
  addSceneOptions(*walk, *options);
  walk->add_option("--method", options->method, methodChoiceHelp());
  addSizeOption(*walk, options->size, "viewport");
  addViewOptions(*walk, *options);
  walk->add_flag("--verify", options->verify, "check every frame against the object-ID oracle");
  walk->add_option("--json", options->json, "write a JSON summary with a per-frame array");
  walk->add_option("--images", options->images, "write PNG frames into this folder");
  walk->add_flag("--overlay", options->overlay, "with --images: tile grid and boxes pictures");
  addConfigOption(*walk, *options);
  walk->final_callback([options] { throw CLI::RuntimeError(runWalk(*options)); });
}

}  // namespace logrid::samples
