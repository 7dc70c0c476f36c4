#include "cli/bench_motion.hpp"

#include <cstdio>
#include <map>
#include <sstream>

#include "cli/option_checks.hpp"
#include "cli/report.hpp"
#include "cli/values.hpp"
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
  std::uint32_t movers = 0;
  double frame_ms = 0;
  double spread = 0;
  std::int64_t missed = -1;
  FrameAverages f;
  double tests() const { return f.boxes_tested; }          // occlusion tests of the culler
  double additional() const { return f.measure_counted; }  // the ternary tree's (§3.3)
  double queries() const { return tests() + additional(); }
  double updateShare() const { return frame_ms > 0 ? f.update_ms / frame_ms : 0; }
};

Row makeRow(const Measured& m, std::uint32_t movers) {
  return {m.label,
          movers,
          m.result.avg_ms(),
          m.result.spread(),
          m.frames.verified ? m.frames.missed : -1,
          m.frames};
}

nlohmann::json rowJson(const Row& r) {
  return {{"hierarchy", r.hierarchy},
          {"frame_ms", r.frame_ms},
          {"spread", r.spread},
          {"update_ms", r.f.update_ms},
          {"update_share", r.updateShare()},
          {"measure_ms", r.f.measure_ms},
          {"drawn_objects", r.f.objects},
          {"drawn_triangles", r.f.triangles},
          {"occlusion_tests", r.tests()},
          {"additional_queries", r.additional()},
          {"queries", r.queries()},
          {"moved_objects", r.f.moved},
          {"colliding_waits", r.f.colliding_waits},
          {"rebuilds", r.f.rebuilds},
          {"splits", r.f.splits},
          {"merges", r.f.merges},
          {"relocated", r.f.relocated},
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

// Every hierarchy's row of the cells of one scene and size, by movers.
void writeRows(std::ostream& md, const std::vector<const Cell*>& cells) {
  std::vector<Row> rows;
  for (const Cell* c : cells) rows.insert(rows.end(), c->rows.begin(), c->rows.end());
  writeTable<Row>(
      md,
      {{"movers", "--:", [](const Row& r) { return grouped(r.movers); }},
       {"hierarchy", "---", [](const Row& r) { return r.hierarchy; }},
       {"update ms", "--:", [](const Row& r) { return formatFixed(r.f.update_ms, 3); }},
       {"share", "--:", [](const Row& r) { return formatFixed(100 * r.updateShare(), 1) + "%"; }},
       {"stats ms", "--:", [](const Row& r) { return formatFixed(r.f.measure_ms, 2); }},
       {"frame ms", "--:", [](const Row& r) { return formatFixed(r.frame_ms); }},
       {"spread", "--:", [](const Row& r) { return formatFixed(100 * r.spread, 0) + "%"; }},
       {"drawn objects", "--:", [](const Row& r) { return grouped(r.f.objects); }},
       {"drawn triangles", "--:", [](const Row& r) { return grouped(r.f.triangles); }},
       {"queries (tests + additional)", "--:",
        [](const Row& r) {
          return grouped(r.queries()) + " (" + grouped(r.tests()) + " + " +
                 grouped(r.additional()) + ")";
        }},
       {"rebuilds / splits / merges", "--:",
        [](const Row& r) {
          return std::to_string(r.f.rebuilds) + " / " + std::to_string(r.f.splits) + " / " +
                 std::to_string(r.f.merges);
        }},
       {"missed",
        "--:", [](const Row& r) { return r.missed >= 0 ? std::to_string(r.missed) : "–"; }}},
      rows);
}

// The paper's Table 1 columns: new (ternary) against old (binary), and against refit.
void writeRatios(std::ostream& md, const std::vector<const Cell*>& cells) {
  md << "\nTable 1 columns as ratios (time, rendered objects, queries per frame):\n\n";
  std::vector<const Cell*> with_ternary;
  for (const Cell* c : cells) {
    if (find(c->rows, "ternary")) with_ternary.push_back(c);
  }
  auto against = [](const char* other, auto value) {
    return [other, value](const Cell* c) {
      const Row* o = find(c->rows, other);
      return o ? formatRatio(value(*find(c->rows, "ternary")), value(*o)) : "–";
    };
  };
  const auto time = [](const Row& r) { return r.frame_ms; };
  const auto objects = [](const Row& r) { return r.f.objects; };
  const auto queries = [](const Row& r) { return r.queries(); };
  writeTable<const Cell*>(md,
                          {{"movers", "--:", [](const Cell* c) { return grouped(c->movers); }},
                           {"ternary ÷ binary: time", "--:", against("binary", time)},
                           {"objects", "--:", against("binary", objects)},
                           {"queries", "--:", against("binary", queries)},
                           {"ternary ÷ refit: time", "--:", against("refit", time)},
                           {"objects", "--:", against("refit", objects)},
                           {"queries", "--:", against("refit", queries)}},
                          with_ternary);
  md << "\nThe paper (new ÷ old, its Table 1):";
  for (const PaperRow& p : kPaper) {
    md << " " << p.scene << " " << formatFixed(p.time, 2) << " / " << formatFixed(p.objects, 2)
       << " / " << formatFixed(p.queries, 2) << ";";
  }
  md << "\n";
}

// Update time, frame time and drawn objects against the number of movers.
void plotCells(Experiment& e, const std::string& scene, const std::string& size,
               const std::vector<const Cell*>& cells, const std::vector<std::string>& hierarchies) {
  PlotAxes axes{"movers", "", PlotScale::Auto, false, {}, true};
  for (std::size_t i = 0; i < cells.size(); ++i) {
    axes.xtics.push_back({double(i), grouped(cells[i]->movers)});
  }
  auto series = [&](auto value) {
    std::vector<PlotSeries> out;
    for (const std::string& h : hierarchies) {
      PlotSeries s{h, {}, {}, {}, {}};
      for (std::size_t i = 0; i < cells.size(); ++i) {
        if (const Row* r = find(cells[i]->rows, h)) {
          s.x.push_back(double(i));
          s.y.push_back(value(*r));
        }
      }
      out.push_back(std::move(s));
    }
    return out;
  };
  const std::string stem = "motion_" + scene + "_" + size;
  const std::string title = scene + " " + size;
  axes.ylabel = "ms";
  plotLines(e.plotStem(stem + "_update"), title + ": hierarchy update per frame", axes,
            series([](const Row& r) { return r.f.update_ms; }));
  plotLines(e.plotStem(stem + "_frame"), title + ": frame time", axes,
            series([](const Row& r) { return r.frame_ms; }));
  axes.ylabel = "objects per frame";
  plotLines(e.plotStem(stem + "_objects"), title + ": drawn objects", axes,
            series([](const Row& r) { return r.f.objects; }));
  const std::string update = e.plotImage("update", stem + "_update");
  if (!update.empty()) {
    e.md() << "\n"
           << update << " " << e.plotImage("frame", stem + "_frame") << " "
           << e.plotImage("objects", stem + "_objects") << "\n";
  }
}

// Where the targets of the motion issue stand.
void writeTargets(std::ostream& md, const std::vector<Cell>& cells) {
  md << "\n## Targets\n\n";
  for (const Cell& c : cells) {
    if (c.movers != 1000) continue;
    for (const Row& r : c.rows) {
      if (c.scene == "city" && c.size == "640x480") {
        md << "- " << (r.updateShare() <= 0.10 ? "met" : "**not met**") << ": city 640×480, "
           << "1,000 movers, " << r.hierarchy << " update " << formatFixed(r.f.update_ms, 2)
           << " ms = " << formatFixed(100 * r.updateShare(), 1) << "% of the frame (≤ 10%)\n";
      }
    }
  }
  for (const Cell& c : cells) {
    const Row* f = find(c.rows, "refit");
    for (const char* name : {"ternary", "ternary-objects"}) {
      const Row* t = find(c.rows, name);
      if (!t || !f || c.movers == 0) continue;
      md << "- " << (t->f.objects < f->f.objects ? "met" : "**not met**") << ": " << c.scene << " "
         << c.size << ", " << grouped(c.movers) << " movers: " << name << " draws "
         << formatRatio(t->f.objects, f->f.objects) << "× refit's objects ("
         << grouped(t->f.objects) << " vs " << grouped(f->f.objects)
         << "; the paper: 0.37–0.93 against its old algorithm)\n";
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
}

std::string intro(const std::string& method, const std::string& lookahead) {
  return "Every hierarchy culls the same frames (interleaved per frame, method " + method +
         ", lookahead " + lookahead +
         "; the ternary tree with colliding-query detection, §3.5). Frame time is hierarchy "
         "update + clear + cull + draw + the ternary tree's statistics pass + glFinish. `update` "
         "is the hierarchy's update per frame, `share` its part of the frame time, `stats` "
         "the ternary tree's additional queries (§3.3). `queries` = occlusion tests + "
         "additional queries. `missed`: visible objects not drawn, every frame of the first "
         "repetition checked against the object-ID oracle.\n";
}

// The hierarchies, each culling with `method` (the ternary tree with colliding-query
// detection).
std::vector<Variant> hierarchyVariants(const std::vector<std::string>& hierarchies,
                                       const std::string& method) {
  std::vector<Variant> out;
  for (const std::string& h : hierarchies) {
    out.push_back({h, [h, method](WalkOptions& o) {
                     o.method = method;
                     o.hierarchy = h;
                     o.colliding = h == "ternary" || o.colliding;
                   }});
  }
  return out;
}

// Every scene with each count of movers at each size: the hierarchies side by side.
std::vector<Cell> measureCells(Experiment& e, const std::vector<std::uint32_t>& counts,
                               const std::vector<Variant>& variants) {
  std::vector<Cell> cells;
  for (const std::string& scene_name : e.options().scenes) {
    for (std::uint32_t n : counts) {
      WalkOptions so = e.sceneOptions(scene_name);
      so.movers = n;
      const LoadedScene scene = e.load(so, variants);
      for (const std::string& size : e.options().sizes) {
        WalkOptions cell = so;
        cell.size = size;
        const std::string label =
            "bench --motion " + scene.prepared.name + " " + std::to_string(n) + " movers " + size;
        const std::vector<Measured> measured = e.run(scene, cell, variants, label);
        Cell c{scene.prepared.name, size, n, {}};
        nlohmann::json cj = scene.describe();
        cj["movers"] = n;
        cj["size"] = size;
        cj["rows"] = nlohmann::json::array();
        for (const Measured& r : measured) {
          c.rows.push_back(makeRow(r, n));
          nlohmann::json rj = rowJson(c.rows.back());
          rj["frame_ms_per_frame"] = r.result.frame_ms;
          cj["rows"].push_back(rj);
        }
        e.report()["cells"].push_back(cj);
        cells.push_back(std::move(c));
      }
    }
  }
  return cells;
}

}  // namespace

void addMotionBenchOptions(CLI::App& bench, MotionBenchOptions& o) {
  bench.add_flag("--motion", o.enabled,
                 "benchmark the hierarchies for moving objects instead (docs/MOTION.md)");
  bench
      .add_option("--movers-list", o.movers,
                  "with --motion: mover counts, comma-separated; each in range " +
                      closed(0u, kMaxMovers).text())
      ->check(numberListCheck(closed(0u, kMaxMovers)));
  bench.add_option("--hierarchies", o.hierarchies,
                   "with --motion: hierarchies, comma-separated (" + bvh::motionNames() + ")");
  bench.add_option("--motion-method", o.method, "with --motion: the culling method");
}

int runMotionBench(const ExperimentOptions& options, const MotionBenchOptions& m) {
  std::vector<std::uint32_t> counts;
  for (const std::string& c : splitList(m.movers)) {
    std::uint32_t n = 0;
    if (!parseNumber(c, n) || n > kMaxMovers) {  // the option's check, for callers without it
      throw Error(ErrorCode::InvalidArgument, "bench --motion: mover count '" + c +
                                                  "' is invalid; use whole numbers up to " +
                                                  std::to_string(kMaxMovers));
    }
    counts.push_back(n);
  }
  const std::vector<std::string> hierarchies = splitList(m.hierarchies);
  for (const std::string& h : hierarchies) {
    if (!bvh::parseMotionKind(h)) {
      throw Error(ErrorCode::InvalidArgument,
                  "bench --motion: hierarchy '" + h + "' is unknown; use " + bvh::motionNames());
    }
  }
  if (counts.empty() || hierarchies.empty()) {
    throw Error(ErrorCode::InvalidArgument,
                "bench --motion: --movers-list and --hierarchies need an entry");
  }
  std::string problem;
  const auto choice = parseMethodChoice(m.method, &problem);
  if (!choice || choice->oracle()) {
    throw Error(
        ErrorCode::InvalidArgument,
        "bench --motion: " +
            (choice ? "method oracle is not a culling method; use " + methodNames() : problem));
  }
  Experiment e(options, "bench --motion", "logrid motion benchmark",
               intro(m.method, options.walk.lookahead));
  e.report()["method"] = m.method;
  e.report()["cells"] = nlohmann::json::array();
  const std::vector<Cell> cells = measureCells(e, counts, hierarchyVariants(hierarchies, m.method));
  bool any_missed = false;
  for (const Cell& c : cells) {
    for (const Row& r : c.rows) any_missed = any_missed || r.missed > 0;
  }

  // Tables per scene and size, rows by movers then hierarchy.
  std::map<std::pair<std::string, std::string>, std::vector<const Cell*>> groups;
  for (const Cell& c : cells) groups[{c.scene, c.size}].push_back(&c);
  for (const auto& [key, list] : groups) {
    const auto& [scene, size] = key;
    e.md() << "\n## " << scene << " " << size << "\n\n";
    writeRows(e.md(), list);
    writeRatios(e.md(), list);
    if (!options.plots.empty()) plotCells(e, scene, size, list, hierarchies);
  }
  writeTargets(e.md(), cells);
  return e.finish(any_missed ? "bench --motion: a hierarchy missed visible objects; that is a bug"
                             : "");
}

}  // namespace logrid::samples
