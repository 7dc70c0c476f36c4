#include "cli/bench_motion.hpp"

#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <sstream>

#include "cli/experiment.hpp"
#include "cli/plot.hpp"
#include "cli/report.hpp"
#include "logrid/error.hpp"
#include "scene/movers.hpp"

namespace logrid::samples {
namespace {

// The paper's Table 1 (new: ternary tree; old: its earlier algorithm), for reference.
struct PaperRow {
  const char* scene;
  double time, objects, queries;  // new ÷ old
};
constexpr PaperRow kPaper[] = {{"power plant + moving bunnies", 0.71, 0.50, 3.82},
                               {"power plant + static bunnies", 0.36, 0.37, 3.54},
                               {"power plant alone", 0.54, 0.41, 3.64},
                               {"teapots (moving)", 0.93, 0.93, 1.55},
                               {"teapots (static)", 0.92, 0.88, 2.04}};

// One hierarchy's figures in one cell (scene, movers, size): averages over the frames
// of the first repetition, frame time the average of per-frame medians.
struct Row {
  std::string hierarchy;
  double frame_ms = 0;
  double spread = 0;
  double update_ms = 0;
  double measure_ms = 0;
  double objects = 0;
  double triangles = 0;
  double tests = 0;       // occlusion tests of the culler
  double additional = 0;  // the ternary tree's Count requests (§3.3)
  double moved = 0;
  double waits = 0;
  std::uint64_t rebuilds = 0, splits = 0, merges = 0, relocated = 0;
  std::int64_t missed = -1;
  double queries() const { return tests + additional; }
  double updateShare() const { return frame_ms > 0 ? update_ms / frame_ms : 0; }
};

Row makeRow(const std::string& hierarchy, const ConfigResult& r) {
  Row row;
  row.hierarchy = hierarchy;
  row.frame_ms = r.avg_ms();
  row.spread = r.spread();
  const double n = r.records.empty() ? 1.0 : double(r.records.size());
  for (const FrameRecord& f : r.records) {
    row.update_ms += f.update.seconds * 1e3 / n;
    row.measure_ms += f.measure.seconds * 1e3 / n;
    row.objects += double(f.stats.objects_drawn) / n;
    row.triangles += double(f.triangles) / n;
    row.tests += double(f.stats.boxes_tested) / n;
    row.additional += double(f.measure.counted) / n;
    row.moved += double(f.moved) / n;
    row.waits += double(f.stats.colliding_waits) / n;
    row.rebuilds += f.update.rebuilds;
    row.splits += f.update.splits;
    row.merges += f.update.merges;
    row.relocated += f.update.relocated;
    if (f.missed >= 0) row.missed = std::max<std::int64_t>(row.missed, 0) + f.missed;
  }
  return row;
}

nlohmann::json rowJson(const Row& r) {
  return {{"hierarchy", r.hierarchy},
          {"frame_ms", r.frame_ms},
          {"spread", r.spread},
          {"update_ms", r.update_ms},
          {"update_share", r.updateShare()},
          {"measure_ms", r.measure_ms},
          {"drawn_objects", r.objects},
          {"drawn_triangles", r.triangles},
          {"occlusion_tests", r.tests},
          {"additional_queries", r.additional},
          {"queries", r.queries()},
          {"moved_objects", r.moved},
          {"colliding_waits", r.waits},
          {"rebuilds", r.rebuilds},
          {"splits", r.splits},
          {"merges", r.merges},
          {"relocated", r.relocated},
          {"missed_visible_objects", r.missed}};
}

const Row* find(const std::vector<Row>& rows, const std::string& h) {
  for (const Row& r : rows) {
    if (r.hierarchy == h) return &r;
  }
  return nullptr;
}

struct Cell {
  std::string scene;
  std::string size;
  std::uint32_t movers = 0;
  std::vector<Row> rows;
};

}  // namespace

void addMotionBenchOptions(CLI::App& bench, MotionBenchOptions& o) {
  bench.add_flag("--motion", o.enabled,
                 "benchmark the hierarchies for moving objects instead (docs/MOTION.md)");
  bench.add_option("--movers-list", o.movers, "with --motion: mover counts, comma-separated");
  bench.add_option("--hierarchies", o.hierarchies,
                   "with --motion: hierarchies, comma-separated (" + bvh::motionNames() + ")");
  bench.add_option("--motion-method", o.method, "with --motion: the culling method");
}

int runMotionBench(const MotionBenchOptions& m, const MotionBenchRun& run) {
  std::vector<std::uint32_t> counts;
  for (const std::string& c : splitList(m.movers)) {
    char* end = nullptr;
    const unsigned long v = std::strtoul(c.c_str(), &end, 10);
    if (!end || *end || c.empty() || c[0] == '-' || v > kMaxMovers) {
      throw Error(ErrorCode::InvalidArgument, "bench --motion: mover count '" + c +
                                                  "' is invalid; use whole numbers up to " +
                                                  std::to_string(kMaxMovers));
    }
    counts.push_back(std::uint32_t(v));
  }
  const std::vector<std::string> hierarchies = splitList(m.hierarchies);
  for (const std::string& h : hierarchies) {
    if (!bvh::parseMotionKind(h)) {
      throw Error(ErrorCode::InvalidArgument,
                  "bench --motion: hierarchy '" + h + "' is unknown; use " + bvh::motionNames());
    }
  }
  if (counts.empty() || hierarchies.empty() || run.scenes.empty() || run.sizes.empty()) {
    throw Error(ErrorCode::InvalidArgument,
                "bench --motion: --movers-list, --hierarchies, --scenes and --sizes need an entry");
  }
  for (const std::string& s : run.sizes) parseSize(s);
  std::string problem;
  const auto choice = parseMethodChoice(m.method, &problem);
  if (!choice || choice->oracle()) {
    throw Error(
        ErrorCode::InvalidArgument,
        "bench --motion: " +
            (choice ? "method oracle is not a culling method; use " + methodNames() : problem));
  }
  if (run.repeat < 1) throw Error(ErrorCode::InvalidArgument, "--repeat must be at least 1");
  if (!run.plots.empty()) std::filesystem::create_directories(run.plots);

  gl::Context context(contextDesc(run.walk));
  const nlohmann::json machine = machineInfo(context);
  std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  nlohmann::json report = {
      {"command", commandLine()}, {"machine", machine}, {"date", date},
      {"repeat", run.repeat},     {"method", m.method}, {"cells", nlohmann::json::array()}};
  std::ostringstream md;
  md << "# logrid motion benchmark\n\nMachine: " << machineLine(machine) << ". " << date
     << ".\n\nCommand: `" << commandLine() << "`\n\n"
     << "Every hierarchy culls the same frames (interleaved per frame, method " << m.method
     << ", lookahead " << run.walk.lookahead
     << "; the ternary tree with colliding-query detection, §3.5). Frame time is hierarchy "
        "update + clear + cull + draw + the ternary tree's statistics pass + glFinish. `update` "
        "is the hierarchy's update per frame, `share` its part of the frame time, `stats` "
        "the ternary tree's additional queries (§3.3). `queries` = occlusion tests + "
        "additional queries. `missed`: visible objects not drawn, every frame of the first "
        "repetition checked against the object-ID oracle.\n";

  std::vector<Cell> cells;
  bool any_missed = false;
  for (const std::string& scene_name : run.scenes) {
    for (std::uint32_t n : counts) {
      WalkOptions so = optionsForScene(run.walk, scene_name, run.forest_scale, run.city_scale);
      so.movers = n;
      LoadedScene scene = loadScene(so);
      for (const std::string& size : run.sizes) {
        std::vector<RunConfig> configs;
        for (const std::string& h : hierarchies) {
          WalkOptions ho = so;
          ho.method = m.method;
          ho.size = size;
          ho.hierarchy = h;
          ho.verify = run.verify;
          ho.colliding = h == "ternary" || so.colliding;
          configs.push_back(runConfig(ho, scene.prepared));
        }
        const std::string label =
            "bench --motion " + scene.prepared.name + " " + std::to_string(n) + " movers " + size;
        const std::vector<ConfigResult> results =
            runInterleaved(scene.prepared, *scene.renderer, configs, run.repeat, label, run.warmup);
        Cell cell{scene.prepared.name, size, n, {}};
        nlohmann::json cj = scene.describe();
        cj["movers"] = n;
        cj["size"] = size;
        cj["rows"] = nlohmann::json::array();
        for (std::size_t c = 0; c < results.size(); ++c) {
          cell.rows.push_back(makeRow(hierarchies[c], results[c]));
          if (cell.rows.back().missed > 0) any_missed = true;
          nlohmann::json rj = rowJson(cell.rows.back());
          rj["frame_ms_per_frame"] = results[c].frame_ms;
          cj["rows"].push_back(rj);
        }
        report["cells"].push_back(cj);
        cells.push_back(std::move(cell));
      }
    }
  }

  // Tables per scene and size, rows by movers then hierarchy.
  std::map<std::pair<std::string, std::string>, std::vector<const Cell*>> groups;
  for (const Cell& c : cells) groups[{c.scene, c.size}].push_back(&c);
  for (const auto& [key, list] : groups) {
    const auto& [scene, size] = key;
    md << "\n## " << scene << " " << size << "\n\n";
    md << "| movers | hierarchy | update ms | share | stats ms | frame ms | spread | drawn objects "
          "| drawn triangles | queries (tests + additional) | rebuilds / splits / merges | missed "
          "|\n|--:|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n";
    for (const Cell* c : list) {
      for (const Row& r : c->rows) {
        md << "| " << grouped(c->movers) << " | " << r.hierarchy << " | "
           << formatFixed(r.update_ms, 3) << " | " << formatFixed(100 * r.updateShare(), 1)
           << "% | " << formatFixed(r.measure_ms, 2) << " | " << formatFixed(r.frame_ms) << " | "
           << formatFixed(100 * r.spread, 0) << "% | " << grouped(r.objects) << " | "
           << grouped(r.triangles) << " | " << grouped(r.queries()) << " (" << grouped(r.tests)
           << " + " << grouped(r.additional) << ") | " << r.rebuilds << " / " << r.splits << " / "
           << r.merges << " | " << (r.missed >= 0 ? std::to_string(r.missed) : "–") << " |\n";
      }
    }
    // The paper's Table 1 columns: new (ternary) against old (binary), and against refit.
    md << "\nTable 1 columns as ratios (time, rendered objects, queries per frame):\n\n"
          "| movers | ternary ÷ binary: time | objects | queries | ternary ÷ refit: time | "
          "objects | queries |\n|--:|--:|--:|--:|--:|--:|--:|\n";
    for (const Cell* c : list) {
      const Row* t = find(c->rows, "ternary");
      const Row* b = find(c->rows, "binary");
      const Row* f = find(c->rows, "refit");
      if (!t) continue;
      md << "| " << grouped(c->movers) << " | " << (b ? formatRatio(t->frame_ms, b->frame_ms) : "–")
         << " | " << (b ? formatRatio(t->objects, b->objects) : "–") << " | "
         << (b ? formatRatio(t->queries(), b->queries()) : "–") << " | "
         << (f ? formatRatio(t->frame_ms, f->frame_ms) : "–") << " | "
         << (f ? formatRatio(t->objects, f->objects) : "–") << " | "
         << (f ? formatRatio(t->queries(), f->queries()) : "–") << " |\n";
    }
    md << "\nThe paper (new ÷ old, its Table 1):";
    for (const PaperRow& p : kPaper) {
      md << " " << p.scene << " " << formatFixed(p.time, 2) << " / " << formatFixed(p.objects, 2)
         << " / " << formatFixed(p.queries, 2) << ";";
    }
    md << "\n";

    if (!run.plots.empty()) {
      const std::string stem = run.plots + "/motion_" + scene + "_" + size;
      std::string xtics = "set xtics (";
      for (std::size_t i = 0; i < list.size(); ++i) {
        xtics += std::string(i ? ", " : "") + "\"" + grouped(list[i]->movers) + "\" " +
                 std::to_string(i);
      }
      xtics += ")\n";
      auto series = [&](auto value) {
        std::vector<PlotSeries> out;
        for (const std::string& h : hierarchies) {
          PlotSeries s{h, {}, {}};
          for (std::size_t i = 0; i < list.size(); ++i) {
            if (const Row* r = find(list[i]->rows, h)) {
              s.x.push_back(double(i));
              s.y.push_back(value(*r));
            }
          }
          out.push_back(std::move(s));
        }
        return out;
      };
      const std::string title = scene + " " + size;
      plotLines(stem + "_update", title + ": hierarchy update per frame", "movers",
                "ms (log scale)", series([](const Row& r) { return r.update_ms; }), true, xtics);
      plotLines(stem + "_frame", title + ": frame time", "movers", "ms",
                series([](const Row& r) { return r.frame_ms; }), false, xtics);
      plotLines(stem + "_objects", title + ": drawn objects", "movers", "objects per frame",
                series([](const Row& r) { return r.objects; }), false, xtics);
      if (!run.markdown.empty()) {
        const std::string link =
            linkFrom(run.markdown, run.plots) + "/motion_" + scene + "_" + size;
        md << "\n![update](" << link << "_update.png) ![frame](" << link
           << "_frame.png) ![objects](" << link << "_objects.png)\n";
      }
    }
  }

  // Where the targets stand.
  md << "\n## Targets\n\n";
  for (const Cell& c : cells) {
    if (c.movers != 1000) continue;
    for (const Row& r : c.rows) {
      if (c.scene == "city" && c.size == "640x480") {
        md << "- " << (r.updateShare() <= 0.10 ? "met" : "**not met**") << ": city 640×480, "
           << "1,000 movers, " << r.hierarchy << " update " << formatFixed(r.update_ms, 2)
           << " ms = " << formatFixed(100 * r.updateShare(), 1) << "% of the frame (≤ 10%)\n";
      }
    }
  }
  for (const Cell& c : cells) {
    const Row* f = find(c.rows, "refit");
    for (const char* name : {"ternary", "ternary-objects"}) {
      const Row* t = find(c.rows, name);
      if (!t || !f || c.movers == 0) continue;
      md << "- " << (t->objects < f->objects ? "met" : "**not met**") << ": " << c.scene << " "
         << c.size << ", " << grouped(c.movers) << " movers: " << name << " draws "
         << formatRatio(t->objects, f->objects) << "× refit's objects (" << grouped(t->objects)
         << " vs " << grouped(f->objects) << "; the paper: 0.37–0.93 against its old algorithm)\n";
    }
  }
  std::int64_t missed = 0;
  bool verified = false;
  for (const Cell& c : cells) {
    for (const Row& r : c.rows) {
      if (r.missed >= 0) verified = true, missed += r.missed;
    }
  }
  md << "- "
     << (!verified     ? "not checked (--no-verify)"
         : missed == 0 ? "met"
                       : "**not met**")
     << ": zero missed visible objects on every moving walkthrough"
     << (verified ? " (" + std::to_string(missed) + " missed)" : "") << "\n";

  std::printf("%s", md.str().c_str());
  if (!run.markdown.empty()) writeText(run.markdown, md.str());
  if (!run.json.empty()) writeJson(run.json, report);
  if (any_missed) {
    std::fprintf(stderr, "bench --motion: a hierarchy missed visible objects; that is a bug\n");
    return 1;
  }
  return 0;
}

}  // namespace logrid::samples
