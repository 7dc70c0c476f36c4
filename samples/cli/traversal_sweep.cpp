#include "cli/traversal_sweep.hpp"

#include <algorithm>
#include <sstream>

#include "cli/readers.hpp"
#include "cli/report.hpp"
#include "cli/values.hpp"
#include "logrid/error.hpp"

namespace logrid::samples {
namespace {

struct Row {
  std::string label;
  std::string method;  // "log-state", "log-zfar", "ddo+log" ... or "oracle"
  std::string reader;
  std::uint32_t lookahead = 1;
  bool coherence = false;
  double ms = 0, spread = 0;
  std::int64_t missed = 0;
  FrameAverages f;
  bool oracle() const { return method == "oracle"; }
};

Row makeRow(const Measured& m) {
  const RunConfig& c = m.result.config;
  return {m.label,
          methodFamily(c),
          c.method.method ? c.reader : "–",
          c.culler.lookahead,
          c.culler.temporal_coherence,
          m.result.avg_ms(),
          m.result.spread(),
          m.frames.verified ? m.frames.missed : 0,
          m.frames};
}

// The oracle, then every method × reader × K × coherence off and on.
std::vector<Variant> sweepVariants(const std::vector<std::string>& methods,
                                   const std::vector<std::string>& readers,
                                   const std::vector<std::uint32_t>& ks) {
  Axis method_axis, reader_axis, k_axis, tc_axis;
  for (const std::string& m : methods) {
    method_axis.push_back({m, [m](WalkOptions& o) { o.method = m; }});
  }
  for (const std::string& r : readers) {
    reader_axis.push_back({r, [r](WalkOptions& o) { o.reader = r; }});
  }
  for (std::uint32_t k : ks) {
    const std::string text = lookaheadText(k);
    k_axis.push_back({"K=" + text, [text](WalkOptions& o) { o.lookahead = text; }});
  }
  for (bool tc : {false, true}) {
    tc_axis.push_back({tc ? "tc" : "", [tc](WalkOptions& o) { o.coherence = tc; }});
  }
  std::vector<Variant> out = {{"oracle", [](WalkOptions& o) {
                                 o.method = "oracle";
                                 o.reader = "readpixels";
                                 o.lookahead = "1";
                                 o.coherence = false;
                               }}};
  for (Variant& v : combine({method_axis, reader_axis, k_axis, tc_axis})) {
    out.push_back(std::move(v));
  }
  return out;
}

void writeSweepTable(std::ostream& md, const std::vector<Row>& rows, const Row& oracle) {
  auto setting = [](auto text) {
    return [text](const Row& r) { return r.oracle() ? std::string("–") : text(r); };
  };
  writeTable<Row>(
      md,
      {{"method", "---", [](const Row& r) { return r.method; }},
       {"reader", "---", [](const Row& r) { return r.reader; }},
       {"K", "--:", setting([](const Row& r) { return lookaheadText(r.lookahead); })},
       {"tc", ":-:", setting([](const Row& r) { return std::string(r.coherence ? "on" : "off"); })},
       {"ms/frame", "--:", [](const Row& r) { return formatFixed(r.ms); }},
       {"spread", "--:", [](const Row& r) { return formatFixed(100 * r.spread, 0) + "%"; }},
       {"÷ oracle", "--:",
        [&oracle](const Row& r) { return oracle.ms > 0 ? formatFixed(r.ms / oracle.ms) : "–"; }},
       {"objects", "--:", [](const Row& r) { return grouped(r.f.objects); }},
       {"triangles", "--:", [](const Row& r) { return grouped(r.f.triangles); }},
       {"flushes", "--:", [](const Row& r) { return formatFixed(r.f.flushes, 1); }},
       {"batches", "--:", [](const Row& r) { return formatFixed(r.f.batches, 1); }},
       {"bytes read", "--:", [](const Row& r) { return grouped(r.f.bytes_read); }},
       {"pixels read", "--:", [](const Row& r) { return grouped(r.f.pixels_read); }},
       {"missed", "--:", [](const Row& r) { return std::to_string(r.missed); }}},
      rows);
}

// Where the targets stand: the fastest exact setting, and the fewest flushes.
void writeBest(std::ostream& md, const std::vector<Row>& rows, const Row& oracle) {
  const Row* best = nullptr;
  const Row* fewest = nullptr;
  for (const Row& r : rows) {
    if (r.oracle() || r.missed > 0) continue;
    if (!best || r.ms < best->ms) best = &r;
    if (!fewest || r.f.flushes < fewest->f.flushes ||
        (r.f.flushes == fewest->f.flushes && r.ms < fewest->ms)) {
      fewest = &r;
    }
  }
  if (best) {
    md << "\nFastest exact setting: **" << best->label << "**, " << formatFixed(best->ms)
       << " ms/frame, " << formatFixed(best->ms / oracle.ms) << "× the oracle's "
       << formatFixed(oracle.ms) << " ms, " << formatFixed(best->f.flushes, 1)
       << " flushes per frame. Fewest flushes: " << fewest->label << ", "
       << formatFixed(fewest->f.flushes, 1) << " per frame, " << formatFixed(fewest->ms)
       << " ms/frame, " << grouped(fewest->f.objects) << " objects.\n";
  }
}

nlohmann::json cellJson(const LoadedScene& scene, const std::string& size,
                        const std::vector<Measured>& measured, const std::vector<Row>& rows) {
  const Row& oracle = rows.front();
  nlohmann::json cell = scene.describe();
  cell["size"] = size;
  cell["configs"] = nlohmann::json::array();
  for (std::size_t c = 0; c < measured.size(); ++c) {
    nlohmann::json j = runSummary(measured[c].result.records, measured[c].result.config, false);
    j["label"] = rows[c].label;
    j["avg_frame_ms"] = rows[c].ms;
    j["spread"] = rows[c].spread;
    j["ms_vs_oracle"] = oracle.ms > 0 ? rows[c].ms / oracle.ms : 0;
    cell["configs"].push_back(std::move(j));
  }
  return cell;
}

// Flushes and frame time against K: a panel per reader, a line per method and coherence,
// the oracle's frame time as a band from its fastest to its slowest repetition.
void plotSweep(Experiment& e, const std::string& stem, const std::string& title,
               const std::vector<Row>& rows, const ConfigResult& oracle,
               const std::vector<std::string>& methods, const std::vector<std::string>& readers,
               const std::vector<std::uint32_t>& ks) {
  PlotAxes axes{"lookahead K", "", PlotScale::Auto, false, {}, true};
  std::vector<double> x;
  for (std::size_t i = 0; i < ks.size(); ++i) {
    x.push_back(double(i));
    axes.xtics.push_back({double(i), lookaheadText(ks[i])});
  }
  const auto [fastest, slowest] =
      std::minmax_element(oracle.repetition_ms.begin(), oracle.repetition_ms.end());
  const PlotSeries floor{"oracle", std::vector<double>(ks.size(), oracle.avg_ms()), x,
                         std::vector<double>(ks.size(), *fastest),
                         std::vector<double>(ks.size(), *slowest)};
  std::vector<PlotPanel> flushes, times;
  for (const std::string& reader : readers) {
    PlotPanel f{"reader " + reader, {}}, t{"reader " + reader, {}};
    for (const std::string& method : methods) {
      for (bool tc : {false, true}) {
        PlotSeries fs{method + (tc ? " tc" : ""), {}, x, {}, {}};
        PlotSeries ts = fs;
        for (std::uint32_t k : ks) {
          for (const Row& r : rows) {
            if (r.method == method && r.reader == reader && r.lookahead == k && r.coherence == tc) {
              fs.y.push_back(std::max(r.f.flushes, 0.1));  // 0.1: no flush, on a log scale
              ts.y.push_back(r.ms);
            }
          }
        }
        f.series.push_back(std::move(fs));
        t.series.push_back(std::move(ts));
      }
    }
    t.series.push_back(floor);
    flushes.push_back(std::move(f));
    times.push_back(std::move(t));
  }
  axes.ylabel = "flushes per frame";
  plotPanels(e.plotStem(stem + "_flushes"), title + ": flushes per frame against lookahead K", axes,
             flushes);
  axes.ylabel = "ms per frame";
  plotPanels(e.plotStem(stem + "_ms"), title + ": frame time against lookahead K", axes, times);
  const std::string images = e.plotImage("flushes", stem + "_flushes");
  if (!images.empty()) e.md() << "\n" << images << " " << e.plotImage("time", stem + "_ms") << "\n";
}

constexpr const char* kIntro =
    "The lazy grid's two variants with every depth source, lookahead K (boxes whose "
    "undecided tiles are read in one batch; `CullerDesc::lookahead`) and temporal "
    "coherence (`tc`: last frame's visible leaves drawn first, then one refresh batch), on "
    "the same frames, interleaved, with the oracle (the exact visible set, drawn) as the "
    "floor. Every configuration is exact: `missed` counts visible objects not drawn, "
    "checked against the object-ID oracle on every frame of the first repetition. "
    "Flushes are the waits for the renderer (each one flushes llvmpipe's deferred "
    "pipeline, or stalls a GPU); batches are submit() calls; bytes are what crossed from "
    "the renderer (depth values, or 16 bytes per rectangle from the compute reduction, or "
    "4 per query result).\n";

}  // namespace

int runTraversalSweep(const ExperimentOptions& options, const std::vector<std::string>& methods,
                      const std::vector<std::string>& readers,
                      const std::vector<std::string>& lookaheads) {
  std::vector<std::uint32_t> ks;
  for (const std::string& k : lookaheads) ks.push_back(parseLookahead(k));
  for (const std::string& r : readers) {
    if (!findReader(r)) {
      throw Error(ErrorCode::InvalidArgument,
                  "bench --traversal: reader '" + r + "' is unknown; use " + readerNames());
    }
  }
  ExperimentOptions checked = options;
  checked.verify = true;  // the sweep reports exact settings only
  Experiment e(checked, "bench --traversal",
               "logrid: lookahead, temporal coherence and depth sources", kIntro);
  e.report()["cells"] = nlohmann::json::array();
  const std::vector<Variant> variants = sweepVariants(methods, readers, ks);
  bool missed = false;
  for (const std::string& scene_name : options.scenes) {
    WalkOptions so = e.sceneOptions(scene_name);
    so.size = options.sizes.front();
    const LoadedScene scene = e.load(so, variants);
    const std::string name = scene.prepared.name;
    const std::vector<Measured> measured =
        e.run(scene, so, variants, "traversal " + name + " " + so.size);
    std::vector<Row> rows;
    for (const Measured& m : measured) rows.push_back(makeRow(m));
    for (const Row& r : rows) missed = missed || (!r.oracle() && r.missed > 0);
    const RunConfig& first = measured.front().result.config;
    e.md() << "\n## " << name << " " << so.size << "\n\n"
           << framesAlong(first.frames, first.time_step) << ", " << options.repeat
           << " interleaved repetitions (ms/frame: average over frames of the per-frame "
              "median).\n\n";
    writeSweepTable(e.md(), rows, rows.front());
    writeBest(e.md(), rows, rows.front());
    e.report()["cells"].push_back(cellJson(scene, so.size, measured, rows));
    if (!options.plots.empty()) {
      plotSweep(e, "traversal_" + name + "_" + so.size, name + " " + so.size, rows,
                measured.front().result, methods, readers, ks);
    }
  }
  return e.finish(missed ? "bench --traversal: an exact configuration missed visible objects "
                           "(see 'missed'); that is a bug, please report it with the command "
                           "line"
                         : "");
}

}  // namespace logrid::samples
