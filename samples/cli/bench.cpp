// logrid bench: every method on the same frames of the same walkthroughs, interleaved
// frame by frame, per scene and viewport size: the paper's Table 1 on our frames, the
// ratios that matter, the depth readers side by side, plots, and where the targets of
// the benchmark issue stand. `--tradeoff` runs the speed-for-accuracy sweep instead
// (tradeoff.cpp), `--traversal` the lookahead / coherence / reader sweep
// (traversal_sweep.cpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <memory>
#include <sstream>

#include "cli/bench_motion.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/experiment.hpp"
#include "cli/plot.hpp"
#include "cli/readers.hpp"
#include "cli/report.hpp"
#include "cli/tradeoff.hpp"
#include "cli/traversal_sweep.hpp"
#include "logrid/error.hpp"
#include "logrid/method.hpp"

namespace logrid::samples {
namespace {

// Table 1 of the paper (LOG §5): per scene and size, LOG, BOG, HZB, PQ and no culling.
struct PaperCell {
  const char* scene;
  std::uint32_t width;
  double seconds[5];     // LOG BOG HZB PQ noOC
  double pixels[4];      // LOG BOG HZB PQ
  double tiles_per_box;  // LOG, 640x480 only (0: not given)
};
constexpr PaperCell kPaper[] = {
    {"forest", 640, {0.018, 0.073, 0.162, 0.152, 0.045}, {198621, 2288217, 2682035, 5880310}, 14.6},
    {"forest", 1280, {0.031, 0.216, 0.632, 0.611, 0.052}, {424713, 6844437, 10729627, 23495623}, 0},
    {"city", 640, {0.021, 0.045, 0.087, 0.158, 0.741}, {283306, 1272965, 1361715, 6032486}, 17.7},
    {"city", 1280, {0.033, 0.138, 0.328, 0.630, 0.742}, {312053, 4230168, 5417068, 24042029}, 0},
};

const PaperCell* paperCell(const std::string& scene, std::uint32_t width) {
  for (const PaperCell& c : kPaper) {
    if (scene == c.scene && width == c.width) return &c;
  }
  return nullptr;
}

// Paper column of a method (index into PaperCell arrays), -1 if the paper has none.
int paperColumn(const std::string& method) {
  if (method == "log-state") return 0;
  if (method == "bog") return 1;
  if (method == "hzb") return 2;
  if (method == "pq") return 3;
  if (method == "vfc") return 4;
  return -1;
}

struct BenchOptions {
  WalkOptions walk;
  std::string scenes = "forest,city";
  std::string sizes = "640x480,1280x960";
  // The paper's methods, then LOG's best exact stall settings measured in
  // docs/TRAVERSAL.md (log-zfar K = 16: fastest without coherence on the forest;
  // log-state K = 32 + tc: under 10 flushes a frame), then the comparison methods.
  std::string methods = "log-state,log-zfar,log-zfar:16,log-state:32:tc,bog,hzb,pq,vfc,oracle";
  std::string readers = "pbo,reduce,query";  // log-state again with these readers
  double forest_scale = 0;                   // 0: --scale
  double city_scale = 0;
  std::size_t repeat = 3;
  std::size_t warmup = 2;
  bool no_verify = false;
  std::string markdown;
  std::string json;
  std::string plots;
  bool tradeoff = false;
  bool traversal = false;
  std::string lookaheads = "1,4,16,64,all";  // --traversal
  MotionBenchOptions motion;                 // --motion: bench_motion.cpp
};

std::string ratio(double a, double b) { return formatRatio(a, b, "×"); }

struct Row {
  std::string label;
  std::string method;
  std::string reader;
  double ms = 0;
  double spread = 0;
  double objects = 0;
  double triangles = 0;
  double pixels = 0;
  double tiles_per_box = 0;
  double read_share = 0;
  double flushes = 0;
  double occluders = -1;     // DDO methods: occluders per frame
  bool box_queries = false;  // a hardware-query method (MethodNeeds::queries)
  double queries = 0, query_waits = 0, query_boxes = 0;
  std::int64_t missed = -1;
  std::int64_t missed_artifacts = 0;  // objects shown only by depth-extrapolated fragments
  bool conservative = true;
};

// A table row from a configuration's result and its runSummary().
Row makeRow(const std::string& label, const ConfigResult& r, const nlohmann::json& s) {
  Row row;
  row.label = label;
  row.method = r.config.method.name();
  // Only methods that read the depth buffer use a reader (MethodNeeds::depth).
  row.reader = r.config.method.method && methodInfo(*r.config.method.method).needs.depth
                   ? r.config.reader
                   : "–";
  row.ms = r.avg_ms();
  row.spread = r.spread();
  row.objects = s["avg_drawn_objects"];
  row.triangles = s["avg_drawn_triangles"];
  row.pixels = s["avg_read_pixels"];
  row.tiles_per_box = s["avg_tiles_per_box"];
  row.read_share = row.ms > 0 ? s["avg_read_ms"].get<double>() / row.ms : 0;
  double flushes = 0;
  for (const FrameRecord& f : r.records) flushes += double(f.stats.flushes);
  row.flushes = r.records.empty() ? 0 : flushes / double(r.records.size());
  if (s.contains("avg_occluders")) row.occluders = s["avg_occluders"];
  if (r.config.method.method && methodInfo(*r.config.method.method).needs.queries) {
    row.box_queries = true;
    row.queries = s["avg_queries"];
    row.query_waits = s["avg_query_waits"];
    double boxes = 0;
    for (const FrameRecord& f : r.records) boxes += double(f.stats.query_boxes);
    row.query_boxes = r.records.empty() ? 0 : boxes / double(r.records.size());
  }
  if (s.contains("missed_visible_objects")) {
    row.missed = s["missed_visible_objects"];
    row.missed_artifacts = s["missed_depth_artifact_objects"];
  }
  row.conservative = r.config.method.method && *r.config.method.method != Method::Vfc
                         ? r.config.culler.approximation.exact()
                         : true;
  return row;
}

const Row* findRow(const std::vector<Row>& rows, const std::string& label) {
  for (const Row& r : rows) {
    if (r.label == label) return &r;
  }
  return nullptr;
}

// The hardware-query methods of a cell (issue 12): queries and waits per frame, and the
// papers' ratios: queries against hwq (Kovalčík & Sochor, CHC++), frame time against the
// oracle (NOHC's Table 4 compares with an optimum). Nothing when no such method ran.
void writeQueryTable(std::ostream& md, const std::vector<Row>& rows) {
  const Row* hwq = findRow(rows, "hwq");
  const Row* oracle = findRow(rows, "oracle");
  bool any = false;
  for (const Row& r : rows) any = any || r.box_queries;
  if (!any) return;
  md << "\nHardware occlusion queries (per frame; a multi-query counts once and draws several "
        "boxes):\n\n"
        "| method | queries | boxes queried | waited for | flushes | queries ÷ hwq | time ÷ hwq "
        "| time ÷ oracle |\n|---|--:|--:|--:|--:|--:|--:|--:|\n";
  for (const Row& r : rows) {
    if (!r.box_queries) continue;
    md << "| " << r.label << " | " << formatFixed(r.queries, 1) << " | "
       << formatFixed(r.query_boxes, 1) << " | " << formatFixed(r.query_waits, 1) << " | "
       << formatFixed(r.flushes, 1) << " | " << (hwq ? ratio(r.queries, hwq->queries) : "–")
       << " | " << (hwq ? ratio(r.ms, hwq->ms) : "–") << " | "
       << (oracle ? ratio(r.ms, oracle->ms) : "–") << " |\n";
  }
}

// The markdown of one scene × size cell: the measured table, the ratios beside the
// paper's, and the targets.
void writeCell(std::ostream& md, const std::string& scene, std::uint32_t width,
               std::uint32_t height, const std::vector<Row>& rows, const RunConfig& config,
               std::size_t repeats, const std::string& plot_prefix) {
  md << "\n### " << scene << " " << width << "×" << height << "\n\n";
  md << framesAlong(config.frames, config.time_step) << ", " << repeats
     << " interleaved repetitions; ms/frame is the average over frames of the per-frame median, "
        "spread is (max − min) / median of the repetitions' averages.\n\n";
  md << "| method | reader | ms/frame | spread | drawn objects | drawn triangles | pixels read "
        "| tiles/box | read share | flushes | missed |\n";
  md << "|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n";
  for (const Row& r : rows) {
    md << "| " << r.label << " | " << r.reader << " | " << formatFixed(r.ms) << " | "
       << formatFixed(100 * r.spread, 0) << "% | " << grouped(r.objects) << " | "
       << grouped(r.triangles) << " | " << grouped(r.pixels) << " | "
       << (r.tiles_per_box > 0 ? formatFixed(r.tiles_per_box) : "–") << " | "
       << formatFixed(100 * r.read_share, 0) << "% | " << formatFixed(r.flushes, 1) << " | "
       << (r.missed >= 0 ? std::to_string(r.missed) : "–")
       << (r.missed_artifacts > 0 ? " (+" + std::to_string(r.missed_artifacts) + " artifact)" : "")
       << " |\n";
  }

  for (const Row& r : rows) {
    if (r.occluders >= 0) {
      md << "\n"
         << r.label << ": " << formatFixed(r.occluders, 1)
         << (r.label == "ddo" ? " octree faces entered into the occlusion map"
                              : " occluder quads drawn before the grid")
         << " per frame.\n";
    }
  }

  writeQueryTable(md, rows);

  const Row* log = findRow(rows, "log-state");
  if (!log) return;
  const PaperCell* paper = paperCell(scene, width);
  md << "\nRatios against LOG (log-state, " << log->reader << ")"
     << (paper ? ", beside the paper's Table 1" : "") << ":\n\n";
  md << "| method | pixels read ÷ LOG | paper | time ÷ LOG | paper |\n|---|--:|--:|--:|--:|\n";
  for (const Row& r : rows) {
    if (r.label == "log-state") continue;
    const int col = paperColumn(r.label);
    md << "| " << r.label << " | " << (r.pixels > 0 ? ratio(r.pixels, log->pixels) : "–") << " | "
       << (paper && col >= 1 && col <= 3 ? ratio(paper->pixels[col], paper->pixels[0]) : "")
       << " | " << ratio(r.ms, log->ms) << " | "
       << (paper && col >= 1 ? ratio(paper->seconds[col], paper->seconds[0]) : "") << " |\n";
  }

  md << "\nTargets (benchmark issue):\n\n";
  auto target = [&](bool met, const std::string& what) {
    md << "- " << (met ? "met" : "**not met**") << ": " << what << "\n";
  };
  if (paper) {
    for (int col = 1; col <= 3; ++col) {
      const char* names[] = {"", "bog", "hzb", "pq"};
      const Row* other = findRow(rows, names[col]);
      if (!other || log->pixels <= 0) continue;
      const double ours = other->pixels / log->pixels;
      const double theirs = paper->pixels[col] / paper->pixels[0];
      target(ours >= theirs, std::string(names[col]) + " reads " + formatFixed(ours, 1) +
                                 "× LOG's pixels (paper " + formatFixed(theirs, 1) + "×)");
    }
  }
  for (const char* name : {"bog", "hzb", "pq", "vfc"}) {
    if (const Row* other = findRow(rows, name)) {
      target(log->ms < other->ms, std::string("LOG faster than ") + name + ": " +
                                      formatFixed(log->ms) + " vs " + formatFixed(other->ms) +
                                      " ms (" + ratio(other->ms, log->ms) + ")");
    }
  }
  const Row* vfc = findRow(rows, "vfc");
  if (scene == "city" && vfc) {
    target(vfc->ms >= 20 * log->ms,
           "city: LOG at least 20× faster than VFC: " + ratio(vfc->ms, log->ms));
  }
  if (const Row* oracle = findRow(rows, "oracle")) {
    target(log->ms <= 1.15 * oracle->ms,
           "LOG within 1.15× of the oracle: " + ratio(log->ms, oracle->ms));
  }
  if (const Row* both = findRow(rows, "ddo+log")) {
    target(both->flushes < log->flushes,
           "ddo+log makes fewer flushes than log-state: " + formatFixed(both->flushes, 1) + " vs " +
               formatFixed(log->flushes, 1));
    target(both->objects <= log->objects,
           "ddo+log draws no more objects than log-state: " + formatFixed(both->objects, 1) +
               " vs " + formatFixed(log->objects, 1));
    target(both->ms < log->ms, "ddo+log faster than log-state: " + formatFixed(both->ms) + " vs " +
                                   formatFixed(log->ms) + " ms (" + ratio(both->ms, log->ms) + ")");
  }
  if (paper && paper->tiles_per_box > 0) {
    target(log->tiles_per_box <= paper->tiles_per_box, "tiles tested per box at most the paper's " +
                                                           formatFixed(paper->tiles_per_box, 1) +
                                                           ": " + formatFixed(log->tiles_per_box));
  }
  if (!plot_prefix.empty()) {
    md << "\n![frame time](" << plot_prefix << "_ms.png) ![pixels read](" << plot_prefix
       << "_pixels.png)\n";
  }
}

int runBench(const BenchOptions& o) {
  if (o.tradeoff)
    return runTradeoff(o.walk, splitList(o.scenes), splitList(o.sizes), o.forest_scale,
                       o.city_scale, o.repeat, o.markdown, o.json, o.plots);
  if (o.motion.enabled) {
    return runMotionBench(
        o.motion, {o.walk, splitList(o.scenes), splitList(o.sizes), o.forest_scale, o.city_scale,
                   o.repeat, o.warmup, !o.no_verify, o.markdown, o.json, o.plots});
  }
  if (o.traversal) {
    TraversalSweepOptions t;
    t.scenes = splitList(o.scenes);
    t.sizes = splitList(o.sizes);
    t.readers = {o.walk.reader};
    for (const std::string& r : splitList(o.readers)) {
      if (std::find(t.readers.begin(), t.readers.end(), r) == t.readers.end())
        t.readers.push_back(r);
    }
    t.lookaheads = splitList(o.lookaheads);
    t.forest_scale = o.forest_scale;
    t.city_scale = o.city_scale;
    t.repeat = o.repeat;
    t.markdown = o.markdown;
    t.json = o.json;
    t.plots = o.plots;
    return runTraversalSweep(o.walk, t);
  }
  if (o.repeat < 1) throw Error(ErrorCode::InvalidArgument, "--repeat must be at least 1");
  const std::vector<std::string> scenes = splitList(o.scenes);
  const std::vector<std::string> sizes = splitList(o.sizes);
  const std::vector<std::string> methods = splitList(o.methods);
  const std::vector<std::string> readers = splitList(o.readers);
  if (scenes.empty() || sizes.empty() || methods.empty()) {
    throw Error(ErrorCode::InvalidArgument, "bench: --scenes, --sizes and --methods need an entry");
  }
  for (const std::string& s : sizes) parseSize(s);  // bad sizes fail before any work
  for (const std::string& m : methods) {
    std::string problem;
    if (!parseMethodChoice(m, &problem))
      throw Error(ErrorCode::InvalidArgument, "bench: " + problem);
  }
  if (!o.plots.empty()) std::filesystem::create_directories(o.plots);

  gl::Context context(contextDesc(o.walk));
  const nlohmann::json machine = machineInfo(context);
  std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));

  std::ostringstream md;
  md << "# logrid benchmark\n\n";
  md << "Machine: " << machineLine(machine) << ". " << date << ".\n\n";
  md << "Command: `" << commandLine() << "`\n\n";
  md << "Every method renders the same frames in turn (interleaved per frame), through the "
        "same traversal and renderer; frame time is clear + cull + draw + glFinish. The "
        "oracle draws exactly the objects an untimed ID pass found visible: the floor no "
        "culling method can beat. `missed` counts visible objects a method did not draw, "
        "checked on every frame of the first repetition against the object-ID oracle; "
        "objects the ID pass shows only through fragments nearer than their own box allows "
        "(llvmpipe's depth extrapolation on edge-on sliver triangles, see "
        "logrid/gl/object_id_oracle.hpp) are counted apart as artifacts.\n";

  nlohmann::json report = {{"command", commandLine()},
                           {"machine", machine},
                           {"date", date},
                           {"repeat", o.repeat},
                           {"cells", nlohmann::json::array()}};
  bool any_missed = false;
  for (const std::string& scene_name : scenes) {
    const WalkOptions so = optionsForScene(o.walk, scene_name, o.forest_scale, o.city_scale);
    bool with_ddo = false;
    for (const std::string& m : methods) with_ddo = with_ddo || needsDdo(m);
    LoadedScene scene = loadScene(so, true, with_ddo);
    const nlohmann::json described = scene.describe();
    md << "\n## " << scene.prepared.name << "\n\n"
       << grouped(double(scene.prepared.triangles)) << " triangles in "
       << grouped(double(scene.prepared.mesh.draws.size())) << " objects (scale " << so.scale
       << ", seed " << so.seed << "); hierarchy of " << scene.prepared.hierarchy.nodes().size()
       << " nodes built in " << formatFixed(scene.prepared.bvh_build_ms, 0) << " ms; generated in "
       << formatFixed(scene.generate_ms, 0) << " ms; peak memory "
       << formatFixed(double(scene.peak_rss_bytes) / double(1 << 20), 0) << " MiB.\n";
    if (scene.ddo) {
      const ddo::Octree& octree = *scene.ddo->octree;
      md << "DDO octree: " << octree.nodes().size() << " nodes, " << octree.params().regions
         << " regions a face, "
         << (scene.ddo->loaded
                 ? "loaded from " + scene.ddo->file + " in " + formatFixed(scene.ddo->load_ms, 0) +
                       " ms"
                 : "built in " + formatFixed(scene.ddo->report.total_ms / 1000, 1) + " s with " +
                       std::to_string(scene.ddo->report.threads) + " threads")
         << "; masks " << formatFixed(double(octree.maskBytes()) / double(1 << 20), 1) << " MiB.\n";
    }

    for (const std::string& size : sizes) {
      std::vector<RunConfig> configs;
      std::vector<std::string> labels;
      auto add = [&](const std::string& method, const std::string& reader,
                     const std::string& label) {
        WalkOptions mo = so;
        mo.method = method;
        mo.reader = reader;
        mo.size = size;
        mo.verify = !o.no_verify;
        configs.push_back(runConfig(mo, scene.prepared));
        labels.push_back(label);
      };
      for (const std::string& m : methods) add(m, so.reader, m);
      for (const std::string& reader : readers) {
        if (reader != so.reader) add("log-state", reader, "log-state (" + reader + ")");
      }
      const auto [w, h] = parseSize(size);
      const std::string label = "bench " + scene.prepared.name + " " + size;
      const std::vector<ConfigResult> results =
          runInterleaved(scene.prepared, *scene.renderer, configs, o.repeat, label, o.warmup);

      std::vector<Row> rows;
      std::vector<std::vector<std::uint64_t>> frame_pixels(
          results.size());  // per config, per frame
      nlohmann::json cell = described;
      cell["width"] = w;
      cell["height"] = h;
      cell["configs"] = nlohmann::json::array();
      for (std::size_t c = 0; c < results.size(); ++c) {
        nlohmann::json j = runSummary(results[c].records, results[c].config, false);
        rows.push_back(makeRow(labels[c], results[c], j));
        for (const FrameRecord& f : results[c].records) {
          frame_pixels[c].push_back(f.stats.pixels_read);
        }
        j["label"] = labels[c];
        j["avg_frame_ms"] = results[c].avg_ms();
        j["spread"] = results[c].spread();
        j["repetition_ms"] = results[c].repetition_ms;
        j["frame_ms"] = results[c].frame_ms;
        j["frame_read_pixels"] = frame_pixels[c];
        cell["configs"].push_back(std::move(j));
        if (rows.back().conservative && rows.back().missed > 0) any_missed = true;
      }
      if (const Row* log = findRow(rows, "log-state")) {
        for (nlohmann::json& j : cell["configs"]) {
          const Row* r = findRow(rows, j["label"]);
          j["time_vs_log"] = log->ms > 0 ? r->ms / log->ms : 0;
          j["pixels_vs_log"] = log->pixels > 0 ? r->pixels / log->pixels : 0;
        }
      }

      std::string plot_prefix;
      if (!o.plots.empty()) {
        const std::string stem = scene.prepared.name + "_" + size;
        std::vector<PlotSeries> ms, px;
        for (std::size_t c = 0; c < results.size(); ++c) {
          ms.push_back({labels[c], results[c].frame_ms, {}});
          if (rows[c].pixels > 0) {
            px.push_back({labels[c], {frame_pixels[c].begin(), frame_pixels[c].end()}, {}});
          }
        }
        const std::string title = scene.prepared.name + " " + size;
        plotLines(o.plots + "/" + stem + "_ms", title + ": frame time", "frame", "ms (log scale)",
                  ms, true);
        plotLines(o.plots + "/" + stem + "_pixels", title + ": depth pixels read", "frame",
                  "pixels (log scale)", px, true);
        if (!o.markdown.empty()) plot_prefix = linkFrom(o.markdown, o.plots) + "/" + stem;
      }
      writeCell(md, scene.prepared.name, w, h, rows, configs.front(), o.repeat, plot_prefix);
      report["cells"].push_back(std::move(cell));
    }
  }
  std::printf("%s", md.str().c_str());
  if (!o.markdown.empty()) writeText(o.markdown, md.str());
  if (!o.json.empty()) writeJson(o.json, report);
  if (any_missed) {
    std::fprintf(stderr,
                 "bench: a conservative method missed visible objects (see 'missed'); "
                 "that is a bug, please report it with the command line\n");
    return 1;
  }
  return 0;
}

}  // namespace

void addBenchCommand(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  o->walk.frames = 40;
  CLI::App* bench = app.add_subcommand("bench", "every method on the same frames, side by side");
  bench->add_option("--scenes", o->scenes, "comma-separated: forest, city, office, model files");
  bench->add_option("--sizes", o->sizes, "comma-separated viewport sizes WIDTHxHEIGHT");
  bench->add_option("--methods", o->methods, "comma-separated: " + methodChoiceHelp());
  bench->add_option("--readers", o->readers,
                    "log-state again with these depth readers (comma-separated: " + readerNames() +
                        "; '' for none)");
  addWalkthroughOptions(*bench, o->walk);
  addViewOptions(*bench, o->walk);  // --tile, --reader, depth, projection, approximate knobs
  bench->add_option("--forest-scale", o->forest_scale, "scale of the forest (default --scale)");
  bench->add_option("--city-scale", o->city_scale, "scale of the city (default --scale)");
  bench->add_option("--repeat", o->repeat, "interleaved repetitions; medians are reported");
  bench->add_option("--warmup", o->warmup, "frames each method renders first, untimed");
  bench->add_flag("--no-verify", o->no_verify, "skip the object-ID check of the first repetition");
  bench->add_option("--markdown", o->markdown, "write the report as markdown");
  bench->add_option("--json", o->json, "write every figure as JSON");
  bench->add_option("--plots", o->plots, "write PNG plots (gnuplot) into this folder");
  bench->add_flag("--tradeoff", o->tradeoff,
                  "sweep the approximate knobs instead: time vs error, Pareto plot");
  bench->add_flag("--traversal", o->traversal,
                  "sweep lookahead K x temporal coherence x --readers for log-state and log-zfar "
                  "instead: flushes, batches, bytes, time against the oracle");
  bench->add_option("--lookaheads", o->lookaheads, "with --traversal: the K values to sweep");
  addMotionBenchOptions(*bench, o->motion);
  bench->final_callback([o] { throw CLI::RuntimeError(runBench(*o)); });
}

}  // namespace logrid::samples
