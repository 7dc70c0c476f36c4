// logrid bench: every method on the same frames of the same walkthroughs, interleaved
// frame by frame, per scene and viewport size: the paper's Table 1 on our frames, the
// ratios that matter, the depth readers side by side, plots, and where the targets of
// the benchmark issue stand. `--tradeoff` runs the speed-for-accuracy sweep instead
// (tradeoff.cpp), `--traversal` the lookahead / coherence / reader sweep
// (traversal_sweep.cpp), `--motion` the hierarchies for moving objects (bench_motion.cpp);
// all four run on the skeleton of experiment.hpp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <memory>
#include <optional>
#include <sstream>

#include "cli/bench_motion.hpp"
#include "cli/cluster_sweep.hpp"
#include "cli/commands.hpp"
#include "cli/config_option.hpp"
#include "cli/experiment.hpp"
#include "cli/option_checks.hpp"
#include "cli/plot.hpp"
#include "cli/readers.hpp"
#include "cli/report.hpp"
#include "cli/tradeoff.hpp"
#include "cli/traversal_sweep.hpp"
#include "cli/values.hpp"
#include "logrid/error.hpp"
#include "logrid/method.hpp"
#include "scene/generators.hpp"

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
  std::string clusters;                      // --clusters: granularities, 0 whole objects
  std::string budgets;                       // --tradeoff: frame-time budgets (ms)
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
  double state_queries = 0;   // GL state queries of the sources (the state guard's cost)
  double occluders = -1;      // DDO methods: occluders per frame
  double occluder_tiles = 0;  // ddo+log: tiles recorded hidden by their coverage per frame
  bool box_queries = false;   // a hardware-query method (MethodNeeds::queries)
  double queries = 0, query_waits = 0, query_boxes = 0;
  std::int64_t missed = -1;
  std::int64_t missed_artifacts = 0;  // objects shown only by depth-extrapolated fragments
  bool conservative = true;
  VerificationCheck verification;  // timed frames with and without the object-ID check
};

// A table row from a configuration's outcome.
Row makeRow(const Measured& m) {
  const ConfigResult& r = m.result;
  const FrameAverages& a = m.frames;
  Row row;
  row.label = m.label;
  row.method = r.config.method.name();
  // Only methods that read the depth buffer use a reader (MethodNeeds::depth).
  row.reader = r.config.method.method && methodInfo(*r.config.method.method).needs.depth
                   ? r.config.reader
                   : "–";
  row.ms = r.avg_ms();
  row.spread = r.spread();
  row.verification = r.verification;
  row.objects = a.objects;
  row.triangles = a.triangles;
  row.pixels = a.pixels_read;
  row.tiles_per_box = a.tiles_per_box;
  row.read_share = row.ms > 0 ? a.read_ms / row.ms : 0;
  row.flushes = a.flushes;
  row.state_queries = a.state_queries;
  if (a.occluders) row.occluders = *a.occluders;
  if (a.occluder_tiles) row.occluder_tiles = *a.occluder_tiles;
  if (r.config.method.method && methodInfo(*r.config.method.method).needs.queries) {
    row.box_queries = true;
    row.queries = a.queries;
    row.query_waits = a.query_waits;
    row.query_boxes = a.query_boxes;
  }
  if (a.verified) {
    row.missed = a.missed;
    row.missed_artifacts = a.missed_artifacts;
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

void writeMethodTable(std::ostream& md, const std::vector<Row>& rows) {
  const std::vector<Column<Row>> columns = {
      {"method", "---", [](const Row& r) { return r.label; }},
      {"reader", "---", [](const Row& r) { return r.reader; }},
      {"ms/frame", "--:", [](const Row& r) { return formatFixed(r.ms); }},
      {"spread", "--:", [](const Row& r) { return formatFixed(100 * r.spread, 0) + "%"; }},
      {"drawn objects", "--:", [](const Row& r) { return grouped(r.objects); }},
      {"drawn triangles", "--:", [](const Row& r) { return grouped(r.triangles); }},
      {"pixels read", "--:", [](const Row& r) { return grouped(r.pixels); }},
      {"tiles/box", "--:",
       [](const Row& r) { return r.tiles_per_box > 0 ? formatFixed(r.tiles_per_box) : "–"; }},
      {"read share", "--:", [](const Row& r) { return formatFixed(100 * r.read_share, 0) + "%"; }},
      {"flushes", "--:", [](const Row& r) { return formatFixed(r.flushes, 1); }},
      {"GL state queries", "--:", [](const Row& r) { return formatFixed(r.state_queries, 1); }},
      {"missed", "--:", [](const Row& r) {
         return (r.missed >= 0 ? std::to_string(r.missed) : "–") +
                (r.missed_artifacts > 0 ? " (+" + std::to_string(r.missed_artifacts) + " artifact)"
                                        : "");
       }}};
  writeTable(md, columns, rows);
}

// Whether verifying a frame changes its timed part (it must not: the ID pass has its own
// framebuffer and runs outside the timer, frame_runner.hpp). From the second repetition,
// which verifies only its odd frames (interleaved.hpp, VerificationCheck).
void writeVerificationCheck(std::ostream& md, const std::vector<Row>& rows) {
  std::vector<Row> checked;
  std::copy_if(rows.begin(), rows.end(), std::back_inserter(checked),
               [](const Row& r) { return r.verification.measured; });
  if (checked.empty()) return;
  md << "\nVerification and timing: the second repetition runs its odd frames with an ID "
        "pass of each row's own (after a method's frame, as verification does; before the "
        "oracle's) and its even frames with none; each frame is taken against its own time "
        "in the first repetition, the even frames giving the drift. Noise is twice the "
        "standard error over the frames; a difference beyond both the spread and the noise "
        "is flagged:\n\n";
  writeTable<Row>(
      md,
      {{"method", "---", [](const Row& r) { return r.label; }},
       {"with ID passes ms",
        "--:", [](const Row& r) { return formatFixed(r.verification.verified_ms); }},
       {"without ms",
        "--:", [](const Row& r) { return formatFixed(r.verification.unverified_ms); }},
       {"difference",
        "--:", [](const Row& r) { return formatFixed(100 * r.verification.difference, 1) + "%"; }},
       {"spread", "--:", [](const Row& r) { return formatFixed(100 * r.spread, 0) + "%"; }},
       {"noise",
        "--:", [](const Row& r) { return formatFixed(100 * r.verification.noise, 0) + "%"; }},
       {"", "---",
        [](const Row& r) {
          return r.verification.flagged(r.spread) ? "**beyond spread and noise**" : "same";
        }}},
      checked);
  for (const Row& r : checked) {
    if (!r.verification.flagged(r.spread)) continue;
    std::fprintf(stderr,
                 "bench: %s: verified frames took %.1f%% %s than the same frames unverified, "
                 "beyond the run's spread (%.0f%%) and noise (%.0f%%): verification is leaking "
                 "into the timed frame, so this row's times are not comparable\n",
                 r.label.c_str(), 100 * std::abs(r.verification.difference),
                 r.verification.difference > 0 ? "longer" : "less", 100 * r.spread,
                 100 * r.verification.noise);
  }
}

void writeOccluderLines(std::ostream& md, const std::vector<Row>& rows) {
  for (const Row& r : rows) {
    if (r.occluders >= 0) {
      md << "\n"
         << r.label << ": " << formatFixed(r.occluders, 1)
         << (r.method == "ddo"
                 ? " octree faces entered into the occlusion map"
                 : " occluder quads recorded in the grid, " + formatFixed(r.occluder_tiles, 1) +
                       " grid tiles recorded hidden by them without a read")
         << " per frame.\n";
    }
  }
}

// The hardware-query methods of a cell (issue 12): queries and waits per frame, and the
// papers' ratios: queries against hwq (Kovalčík & Sochor, CHC++), frame time against the
// oracle (NOHC's Table 4 compares with an optimum). Nothing when no such method ran.
void writeQueryTable(std::ostream& md, const std::vector<Row>& rows) {
  std::vector<Row> queried;
  std::copy_if(rows.begin(), rows.end(), std::back_inserter(queried),
               [](const Row& r) { return r.box_queries; });
  if (queried.empty()) return;
  const Row* hwq = findRow(rows, "hwq");
  const Row* oracle = findRow(rows, "oracle");
  auto against = [](const Row* base, double Row::*field) {
    return [base, field](const Row& r) { return base ? ratio(r.*field, base->*field) : "–"; };
  };
  md << "\nHardware occlusion queries (per frame; a multi-query counts once and draws several "
        "boxes):\n\n";
  writeTable<Row>(
      md,
      {{"method", "---", [](const Row& r) { return r.label; }},
       {"queries", "--:", [](const Row& r) { return formatFixed(r.queries, 1); }},
       {"boxes queried", "--:", [](const Row& r) { return formatFixed(r.query_boxes, 1); }},
       {"waited for", "--:", [](const Row& r) { return formatFixed(r.query_waits, 1); }},
       {"flushes", "--:", [](const Row& r) { return formatFixed(r.flushes, 1); }},
       {"queries ÷ hwq", "--:", against(hwq, &Row::queries)},
       {"time ÷ hwq", "--:", against(hwq, &Row::ms)},
       {"time ÷ oracle", "--:", against(oracle, &Row::ms)}},
      queried);
}

// Every method against LOG, beside the paper's Table 1 where it has the cell.
void writeRatios(std::ostream& md, const std::vector<Row>& rows, const Row& log,
                 const PaperCell* paper) {
  md << "\nRatios against LOG (log-state, " << log.reader << ")"
     << (paper ? ", beside the paper's Table 1" : "") << ":\n\n";
  std::vector<Row> others;
  std::copy_if(rows.begin(), rows.end(), std::back_inserter(others),
               [](const Row& r) { return r.label != "log-state"; });
  writeTable<Row>(
      md,
      {{"method", "---", [](const Row& r) { return r.label; }},
       {"pixels read ÷ LOG",
        "--:", [&log](const Row& r) { return r.pixels > 0 ? ratio(r.pixels, log.pixels) : "–"; }},
       {"paper", "--:",
        [paper](const Row& r) {
          const int col = paperColumn(r.label);
          return paper && col >= 1 && col <= 3 ? ratio(paper->pixels[col], paper->pixels[0])
                                               : std::string();
        }},
       {"time ÷ LOG", "--:", [&log](const Row& r) { return ratio(r.ms, log.ms); }},
       {"paper", "--:",
        [paper](const Row& r) {
          const int col = paperColumn(r.label);
          return paper && col >= 1 ? ratio(paper->seconds[col], paper->seconds[0]) : std::string();
        }}},
      others);
}

// Where the targets of the benchmark issue stand in this cell.
void writeTargets(std::ostream& md, const std::string& scene, const std::vector<Row>& rows,
                  const Row& log, const PaperCell* paper) {
  md << "\nTargets (benchmark issue):\n\n";
  auto target = [&](bool met, const std::string& what) {
    md << "- " << (met ? "met" : "**not met**") << ": " << what << "\n";
  };
  if (paper) {
    for (int col = 1; col <= 3; ++col) {
      const char* names[] = {"", "bog", "hzb", "pq"};
      const Row* other = findRow(rows, names[col]);
      if (!other || log.pixels <= 0) continue;
      const double ours = other->pixels / log.pixels;
      const double theirs = paper->pixels[col] / paper->pixels[0];
      target(ours >= theirs, std::string(names[col]) + " reads " + formatFixed(ours, 1) +
                                 "× LOG's pixels (paper " + formatFixed(theirs, 1) + "×)");
    }
  }
  for (const char* name : {"bog", "hzb", "pq", "vfc"}) {
    if (const Row* other = findRow(rows, name)) {
      target(log.ms < other->ms, std::string("LOG faster than ") + name + ": " +
                                     formatFixed(log.ms) + " vs " + formatFixed(other->ms) +
                                     " ms (" + ratio(other->ms, log.ms) + ")");
    }
  }
  const Row* vfc = findRow(rows, "vfc");
  if (scene == "city" && vfc) {
    target(vfc->ms >= 20 * log.ms,
           "city: LOG at least 20× faster than VFC: " + ratio(vfc->ms, log.ms));
  }
  if (const Row* oracle = findRow(rows, "oracle")) {
    target(log.ms <= 1.15 * oracle->ms,
           "LOG within 1.15× of the oracle: " + ratio(log.ms, oracle->ms));
  }
  if (const Row* both = findRow(rows, "ddo+log")) {
    target(both->flushes < log.flushes,
           "ddo+log makes fewer flushes than log-state: " + formatFixed(both->flushes, 1) + " vs " +
               formatFixed(log.flushes, 1));
    target(both->objects <= log.objects,
           "ddo+log draws no more objects than log-state: " + formatFixed(both->objects, 1) +
               " vs " + formatFixed(log.objects, 1));
    target(both->ms < log.ms, "ddo+log faster than log-state: " + formatFixed(both->ms) + " vs " +
                                  formatFixed(log.ms) + " ms (" + ratio(both->ms, log.ms) + ")");
  }
  if (paper && paper->tiles_per_box > 0) {
    target(log.tiles_per_box <= paper->tiles_per_box, "tiles tested per box at most the paper's " +
                                                          formatFixed(paper->tiles_per_box, 1) +
                                                          ": " + formatFixed(log.tiles_per_box));
  }
}

// The markdown of one scene × size cell: the measured table, the ratios beside the
// paper's, the targets and the plots.
void writeCell(std::ostream& md, const std::string& scene, std::uint32_t width,
               std::uint32_t height, const std::vector<Row>& rows, const RunConfig& config,
               std::size_t repeats, const std::string& images) {
  md << "\n### " << scene << " " << width << "×" << height << "\n\n";
  md << framesAlong(config.frames, config.time_step) << ", " << repeats
     << " interleaved repetitions; ms/frame is the average over frames of the per-frame median, "
        "spread is (max − min) / median of the repetitions' averages.\n\n";
  writeMethodTable(md, rows);
  writeVerificationCheck(md, rows);
  writeOccluderLines(md, rows);
  writeQueryTable(md, rows);
  const Row* log = findRow(rows, "log-state");
  if (!log) return;
  const PaperCell* paper = paperCell(scene, width);
  writeRatios(md, rows, *log, paper);
  writeTargets(md, scene, rows, *log, paper);
  if (!images.empty()) md << "\n" << images << "\n";
}

// The cell's figures: the scene's description and every configuration's summary with its
// frame times and pixels read per frame.
nlohmann::json cellJson(const nlohmann::json& scene, std::uint32_t width, std::uint32_t height,
                        const std::vector<Measured>& measured, const std::vector<Row>& rows) {
  nlohmann::json cell = scene;
  cell["width"] = width;
  cell["height"] = height;
  cell["configs"] = nlohmann::json::array();
  const Row* log = findRow(rows, "log-state");
  for (std::size_t c = 0; c < measured.size(); ++c) {
    const ConfigResult& r = measured[c].result;
    nlohmann::json j = runSummary(r.records, r.config, false);
    std::vector<std::uint64_t> pixels;
    for (const FrameRecord& f : r.records) pixels.push_back(f.stats.pixels_read);
    j["label"] = rows[c].label;
    j["avg_frame_ms"] = r.avg_ms();
    j["spread"] = r.spread();
    j["repetition_ms"] = r.repetition_ms;
    j["frame_ms"] = r.frame_ms;
    j["frame_read_pixels"] = pixels;
    if (r.verification.measured) {
      j["verification_check"] = {{"verified_ms", r.verification.verified_ms},
                                 {"unverified_ms", r.verification.unverified_ms},
                                 {"difference", r.verification.difference},
                                 {"noise", r.verification.noise},
                                 {"flagged", r.verification.flagged(r.spread())}};
    }
    if (log) {
      j["time_vs_log"] = log->ms > 0 ? rows[c].ms / log->ms : 0;
      j["pixels_vs_log"] = log->pixels > 0 ? rows[c].pixels / log->pixels : 0;
    }
    cell["configs"].push_back(std::move(j));
  }
  return cell;
}

// Frame time and pixels read per frame, a panel per method family, the oracle's frame
// time as a band (fastest to slowest repetition) in each panel of frame times.
void plotCell(const Experiment& e, const std::string& stem, const std::string& title,
              const std::vector<Measured>& measured, const std::vector<Row>& rows) {
  std::optional<PlotSeries> oracle;
  for (const Measured& m : measured) {
    const ConfigResult& r = m.result;
    if (m.label == "oracle") oracle = {"oracle", r.frame_ms, {}, r.frame_ms_low, r.frame_ms_high};
  }
  const auto ms = familyPanels(
      measured,
      [](const Measured& m) -> std::optional<PlotSeries> {
        if (m.label == "oracle") return std::nullopt;
        return PlotSeries{m.label, m.result.frame_ms, {}, {}, {}};
      },
      oracle);
  const auto px = familyPanels(measured, [&](const Measured& m) -> std::optional<PlotSeries> {
    if (!(findRow(rows, m.label)->pixels > 0)) return std::nullopt;
    PlotSeries s{m.label, {}, {}, {}, {}};
    for (const FrameRecord& f : m.result.records) s.y.push_back(double(f.stats.pixels_read));
    return s;
  });
  plotPanels(e.plotStem(stem + "_ms"), title + ": frame time",
             {"frame", "ms", PlotScale::Auto, false, {}, true}, ms);
  plotPanels(e.plotStem(stem + "_pixels"), title + ": depth pixels read",
             {"frame", "pixels", PlotScale::Auto, false, {}, true}, px);
}

// The scene's heading: its size, hierarchy, and the DDO octree when it has one.
void writeScene(std::ostream& md, const LoadedScene& scene, const WalkOptions& so) {
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
}

constexpr const char* kIntro =
    "Every method renders the same frames in turn (interleaved per frame), through the "
    "same traversal and renderer, into the same framebuffer (colour and depth: the ID "
    "pass has its own); frame time is clear + cull + draw + glFinish. The oracle draws "
    "exactly the objects an untimed ID pass found visible: the floor no culling method "
    "can beat. `missed` counts visible objects a method did not draw, checked on every "
    "frame of the first repetition against the object-ID oracle, whose passes run before "
    "any frame is timed; "
    "objects the ID pass shows only through fragments nearer than their own box allows "
    "(llvmpipe's depth extrapolation on edge-on sliver triangles, see "
    "logrid/gl/object_id_oracle.hpp) are counted apart as artifacts. The counts (objects, "
    "triangles, pixels read, flushes) are the first repetition's; `auto`, whose culler "
    "goes on learning across the repetitions, may run other settings in the later "
    "ones.\n";

// The methods (each with the command's reader), then log-state with each other reader.
std::vector<Variant> methodVariants(const std::vector<std::string>& methods,
                                    const std::vector<std::string>& readers,
                                    const std::string& reader) {
  std::vector<Variant> out;
  for (const std::string& m : methods) out.push_back({m, [m](WalkOptions& o) { o.method = m; }});
  for (const std::string& r : readers) {
    if (r == reader) continue;
    out.push_back({"log-state (" + r + ")", [r](WalkOptions& o) {
                     o.method = "log-state";
                     o.reader = r;
                   }});
  }
  return out;
}

int runMethods(const ExperimentOptions& eo, const std::vector<std::string>& methods,
               const std::vector<std::string>& readers) {
  if (methods.empty()) throw Error(ErrorCode::InvalidArgument, "bench: --methods needs an entry");
  for (const std::string& m : methods) {
    std::string problem;
    if (!parseMethodChoice(m, &problem))
      throw Error(ErrorCode::InvalidArgument, "bench: " + problem);
  }
  Experiment e(eo, "bench", "logrid benchmark", kIntro);
  e.report()["cells"] = nlohmann::json::array();
  const std::vector<Variant> variants = methodVariants(methods, readers, eo.walk.reader);
  bool any_missed = false;
  for (const std::string& scene_name : eo.scenes) {
    const WalkOptions so = e.sceneOptions(scene_name);
    const LoadedScene scene = e.load(so, variants);
    const nlohmann::json described = scene.describe();
    writeScene(e.md(), scene, so);
    for (const std::string& size : eo.sizes) {
      WalkOptions cell = so;
      cell.size = size;
      const std::string name = scene.prepared.name;
      const std::vector<Measured> measured =
          e.run(scene, cell, variants, "bench " + name + " " + size);
      std::vector<Row> rows;
      for (const Measured& m : measured) rows.push_back(makeRow(m));
      for (const Row& r : rows) any_missed = any_missed || (r.conservative && r.missed > 0);
      const auto [w, h] = parseSize(size);
      const std::string stem = name + "_" + size;
      if (!eo.plots.empty()) plotCell(e, stem, name + " " + size, measured, rows);
      std::string images = e.plotImage("frame time", stem + "_ms");
      if (!images.empty()) images += " " + e.plotImage("pixels read", stem + "_pixels");
      writeCell(e.md(), name, w, h, rows, measured.front().result.config, eo.repeat, images);
      e.report()["cells"].push_back(cellJson(described, w, h, measured, rows));
    }
  }
  return e.finish(any_missed ? "bench: a conservative method missed visible objects (see "
                               "'missed'); that is a bug, please report it with the command line"
                             : "");
}

// What bench's options give every experiment.
ExperimentOptions experimentOptions(const BenchOptions& o) {
  ExperimentOptions e;
  e.walk = o.walk;
  e.scenes = splitList(o.scenes);
  e.sizes = splitList(o.sizes);
  e.forest_scale = o.forest_scale;
  e.city_scale = o.city_scale;
  e.repeat = o.repeat;
  e.warmup = o.warmup;
  e.verify = !o.no_verify;
  e.markdown = o.markdown;
  e.json = o.json;
  e.plots = o.plots;
  return e;
}

int runBench(const BenchOptions& o) {
  const ExperimentOptions e = experimentOptions(o);
  if (o.tradeoff) {
    std::vector<double> budgets;
    for (const std::string& item : splitList(o.budgets)) {
      double ms = 0;
      parseNumber(item, ms);  // checked by the option's numberListCheck
      budgets.push_back(ms);
    }
    return runTradeoff(e, budgets);
  }
  if (o.motion.enabled) return runMotionBench(e, o.motion);
  if (!o.clusters.empty()) {
    std::vector<std::uint32_t> sizes;
    for (const std::string& item : splitList(o.clusters)) {
      std::uint32_t n = 0;
      parseNumber(item, n);  // checked by the option's numberListCheck
      ClusterOptions c;
      c.triangles = n;
      if (const std::string problem = validateClusterOptions(c); !problem.empty()) {
        throw Error(ErrorCode::InvalidArgument, "bench --clusters: " + problem);
      }
      sizes.push_back(n);
    }
    return runClusterSweep(e, splitList(o.methods), sizes);
  }
  if (o.traversal) {
    // The command's reader first, then --readers.
    std::vector<std::string> readers = {o.walk.reader};
    for (const std::string& r : splitList(o.readers)) {
      if (std::find(readers.begin(), readers.end(), r) == readers.end()) readers.push_back(r);
    }
    return runTraversalSweep(e, {"log-state", "log-zfar"}, readers, splitList(o.lookaheads));
  }
  return runMethods(e, splitList(o.methods), splitList(o.readers));
}

}  // namespace

void addBenchCommand(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  o->walk.frames = 40;
  CLI::App* bench = app.add_subcommand("bench", "every method on the same frames, side by side");
  bench->add_option("--scenes", o->scenes, "comma-separated: forest, city, office, model files");
  bench->add_option("--sizes", o->sizes, "comma-separated viewport sizes " + sizeForm())
      ->check(sizeListCheck());
  bench->add_option("--methods", o->methods, "comma-separated: " + methodChoiceHelp());
  bench->add_option("--readers", o->readers,
                    "log-state again with these depth readers (comma-separated: " + readerNames() +
                        "; '' for none)");
  addWalkthroughOptions(*bench, o->walk);
  addViewOptions(*bench, o->walk);  // --tile, --reader, depth, projection, approximate knobs
  addNumber(*bench, "--forest-scale", o->forest_scale, closed(0.0, kMaxForestScale),
            "scale of the forest (default 0: --scale)");
  addNumber(*bench, "--city-scale", o->city_scale, closed(0.0, kMaxCityScale),
            "scale of the city (default 0: --scale)");
  addNumber(*bench, "--repeat", o->repeat, closed<std::size_t>(1, kMaxRepeats),
            "interleaved repetitions; medians are reported");
  addNumber(*bench, "--warmup", o->warmup, closed<std::size_t>(0, kMaxRepeats),
            "frames each configuration renders first, untimed");
  bench->add_flag("--no-verify", o->no_verify, "skip the object-ID check of the first repetition");
  bench->add_option("--markdown", o->markdown, "write the report as markdown");
  bench->add_option("--json", o->json, "write every figure as JSON");
  bench->add_option("--plots", o->plots, "write PNG plots (gnuplot) into this folder");
  bench->add_flag("--tradeoff", o->tradeoff,
                  "sweep the approximate knobs instead: time vs error, Pareto plot");
  bench->add_flag("--traversal", o->traversal,
                  "sweep lookahead K x temporal coherence x --readers for log-state and log-zfar "
                  "instead: flushes, batches, bytes, time against the oracle");
  const NumberRange<double> budget_range{0, 1e6, true, false, {}};
  bench
      ->add_option("--budgets", o->budgets,
                   "with --tradeoff: frame-time budgets in ms, comma-separated, each in range " +
                       budget_range.text() +
                       "; each runs log-state with --budget-ms B beside the fixed settings: "
                       "mean and 95th-percentile time, frames over budget, error")
      ->check(numberListCheck(budget_range));
  bench
      ->add_option(
          "--lookaheads", o->lookaheads,
          "with --traversal: the K values to sweep, comma-separated; each " + lookaheadRange())
      ->check(lookaheadListCheck());
  bench
      ->add_option("--clusters", o->clusters,
                   "run --methods on each scene prepared at each of these granularities instead, "
                   "all interleaved, against the cluster and the object oracle: triangles per "
                   "cluster, comma-separated, each in range " +
                       closed(0u, 512u).text() + " and a multiple of 4 (0: whole objects)")
      ->check(numberListCheck(closed(0u, 512u)));
  addMotionBenchOptions(*bench, o->motion);
  addConfigOption(*bench, o->walk, [o](const std::string& method) { o->methods += "," + method; });
  bench->final_callback([o] { throw CLI::RuntimeError(runBench(*o)); });
}

}  // namespace logrid::samples
