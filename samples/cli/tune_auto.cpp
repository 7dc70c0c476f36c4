// logrid tune --auto. The space is swept in stages, each stage's candidates on the same
// frames, interleaved (interleaved.hpp), each starting from the best of the one before:
//   1. method: frustum culling alone (vfc), log-state and log-zfar at lookahead 1 and 16,
//      each with and without temporal coherence, and auto;
//   2. lookahead around the best grid setting's (K / 4 and K x 4);
//   3. tile size (8, 16, 32, 64);
//   4. depth reader (readpixels, pbo, reduce);
//   5. box granularity (leaf sizes; the forest's tree parts; clusters of 64 and 128
//      triangles), one scene each, runs alternating per repetition.
// A stage is skipped where it cannot matter (no grid: no tile size; no depth read: no
// reader). What the scene needed is read off stage 1: occlusion tests pay only if a
// grid setting beats vfc by the margin, batching only if K > 1 beats K = 1, coherence
// only if it beats going without; stage 1 then keeps the fastest setting that uses no
// part found not needed (pickNeeded), and stage 2 runs only where batching was needed.
#include "cli/tune_auto.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

#include "cli/common.hpp"
#include "cli/config_option.hpp"
#include "cli/interleaved.hpp"
#include "cli/loaded_scene.hpp"
#include "cli/machine.hpp"
#include "cli/report.hpp"
#include "cli/summary.hpp"
#include "logrid/config.hpp"
#include "logrid/error.hpp"

namespace logrid::samples {
namespace {

// A setting is only said to pay when it is this much faster than going without it:
// below it, the difference is within the repetitions' noise on a loaded machine.
constexpr double kPaysMargin = 0.03;

struct Candidate {
  WalkOptions options;  // method (a choice with :K and :tc), tile, reader, granularity
  double ms = 0;
  std::int64_t missed = -1;
};

struct Stage {
  std::string name;
  std::vector<Candidate> candidates;
  std::size_t best = 0;
};

std::string describe(const WalkOptions& o) {
  std::string out = o.method + " tile " + std::to_string(o.tile) + " " + o.reader;
  if (o.leaf) out += " leaf " + std::to_string(o.leaf);
  if (o.tree_parts != "whole") out += " " + o.tree_parts;
  if (o.cluster) out += " cluster " + std::to_string(o.cluster);
  return out;
}

const MethodInfo& infoOf(const WalkOptions& o) {
  const auto choice = parseMethodChoice(o.method);
  return methodInfo(*choice->method);
}

// The candidates on one loaded scene, interleaved.
void runOnScene(LoadedScene& scene, std::vector<Candidate>& candidates, std::size_t repeat,
                const std::string& label) {
  std::vector<RunConfig> configs;
  for (const Candidate& c : candidates) configs.push_back(runConfig(c.options, scene.prepared));
  const std::vector<ConfigResult> results =
      runInterleaved(scene.prepared, *scene.renderer, configs, repeat, label);
  for (std::size_t i = 0; i < results.size(); ++i) {
    candidates[i].ms = results[i].avg_ms();
    candidates[i].missed = runSummary(results[i].records, results[i].config, false)
                               .value("missed_visible_objects", std::int64_t{-1});
  }
}

void pickBest(Stage& s) {
  s.best = 0;
  for (std::size_t i = 1; i < s.candidates.size(); ++i) {
    if (s.candidates[i].ms < s.candidates[s.best].ms) s.best = i;
  }
}

void print(const Stage& s) {
  std::printf("%s\n", s.name.c_str());
  for (std::size_t i = 0; i < s.candidates.size(); ++i) {
    const Candidate& c = s.candidates[i];
    std::printf("  %-44s %9.2f ms %8s%s\n", describe(c.options).c_str(), c.ms,
                c.missed >= 0 ? (std::to_string(c.missed) + " missed").c_str() : "",
                i == s.best ? "   <- best" : "");
  }
}

// The fastest of the candidates whose method choice satisfies `keep`; nullptr if none.
const Candidate* fastest(const Stage& s, const std::function<bool(const MethodChoice&)>& keep) {
  const Candidate* best = nullptr;
  for (const Candidate& c : s.candidates) {
    const auto choice = parseMethodChoice(c.options.method);
    if (choice && keep(*choice) && (!best || c.ms < best->ms)) best = &c;
  }
  return best;
}

// "needed" when `with` is faster than `without` by the margin.
nlohmann::json verdict(const char* what, const Candidate* with, const Candidate* without) {
  nlohmann::json v{{"part", what}};
  if (!with || !without) {
    v["needed"] = nullptr;
    return v;
  }
  v["needed"] = with->ms < (1 - kPaysMargin) * without->ms;
  v["with"] = describe(with->options);
  v["with_ms"] = with->ms;
  v["without"] = describe(without->options);
  v["without_ms"] = without->ms;
  return v;
}

WalkOptions withMethod(const WalkOptions& base, const std::string& method) {
  WalkOptions o = base;
  o.method = method;
  return o;
}

std::string choiceName(Method m, std::uint32_t k, bool tc) {
  MethodChoice c(m);
  c.lookahead = k;
  c.coherence = tc;
  return c.name();
}

// What the scene needed, from stage 1 (same frames, same tile and reader): occlusion
// tests, batched reads, temporal coherence, each a verdict (needed, or null where a side
// had no candidate).
nlohmann::json neededParts(const Stage& first) {
  const auto grid = [](const MethodChoice& c) {
    return c.method && *c.method != Method::Auto && methodInfo(*c.method).grid;
  };
  const auto best = [&](const std::function<bool(const MethodChoice&)>& keep) {
    return fastest(first, keep);
  };
  const Candidate* vfc = best([](const MethodChoice& c) { return c.method == Method::Vfc; });
  const Candidate* any_grid = best(grid);
  const Candidate* batched =
      best([&](const MethodChoice& c) { return grid(c) && c.lookahead.value_or(1) > 1; });
  const Candidate* unbatched =
      best([&](const MethodChoice& c) { return grid(c) && c.lookahead.value_or(1) == 1; });
  const Candidate* coherent = best([&](const MethodChoice& c) { return grid(c) && c.coherence; });
  const Candidate* incoherent =
      best([&](const MethodChoice& c) { return grid(c) && !c.coherence; });
  return {verdict("occlusion tests (against frustum culling alone)", any_grid, vfc),
          verdict("batched reads (lookahead > 1)", batched, unbatched),
          verdict("temporal coherence", coherent, incoherent)};
}

// False only where the verdict says not needed.
bool mayUse(const nlohmann::json& verdict) {
  return verdict["needed"].is_null() || verdict["needed"].get<bool>();
}

// Stage 1's choice, modelling only what the scene requires: the fastest candidate that
// uses no part the verdicts call not needed (auto, which may use every part, only where
// all are needed). So the configuration never keeps a part its own report calls not
// needed.
void pickNeeded(Stage& s, const nlohmann::json& needed) {
  const bool tests = mayUse(needed[0]), batching = mayUse(needed[1]), coherence = mayUse(needed[2]);
  const Candidate* chosen = fastest(s, [&](const MethodChoice& c) {
    if (!c.method || !methodInfo(*c.method).grid) return true;  // frustum culling alone
    if (!tests) return false;
    if (*c.method == Method::Auto) return batching && coherence;
    return (batching || c.lookahead.value_or(1) == 1) && (coherence || !c.coherence);
  });
  if (chosen) {
    s.best = std::size_t(chosen - s.candidates.data());
  } else {
    pickBest(s);  // no frustum-culling candidate, and every grid one uses an unneeded part
  }
}

Stage methodStage(const WalkOptions& base) {
  Stage s{"1. method, lookahead, coherence", {}, 0};
  s.candidates.push_back({withMethod(base, "vfc")});
  for (Method m : {Method::LogState, Method::LogZfar}) {
    for (std::uint32_t k : {1u, 16u}) {
      for (bool tc : {false, true}) {
        s.candidates.push_back({withMethod(base, choiceName(m, k, tc))});
      }
    }
  }
  s.candidates.push_back({withMethod(base, "auto")});
  return s;
}

// `best`, then `best` with each other value of `values` in its `field`.
template <typename Field, typename Value>
Stage variantStage(std::string name, const WalkOptions& best, Field WalkOptions::*field,
                   std::initializer_list<Value> values) {
  Stage s{std::move(name), {{best}}, 0};
  for (const Value& v : values) {
    if (v == best.*field) continue;
    WalkOptions w = best;
    w.*field = v;
    s.candidates.push_back({w});
  }
  return s;
}

// Lookahead around the best grid setting's: K / 4 and K x 4.
Stage lookaheadStage(const WalkOptions& best, const MethodChoice& choice) {
  Stage s{"2. lookahead", {{best}}, 0};
  for (std::uint32_t k : {*choice.lookahead / 4, *choice.lookahead * 4}) {
    if (k < 1) continue;
    s.candidates.push_back({withMethod(best, choiceName(*choice.method, k, choice.coherence))});
  }
  return s;
}

// Leaf sizes, for the forest its trees' trunk and crown apart, and clusters of 64 and
// 128 triangles (clusters.hpp).
Stage granularityStage(const WalkOptions& best, const std::string& scene) {
  Stage s = variantStage("5. box granularity", best, &WalkOptions::leaf, {1u, 4u});
  if (scene == "forest" && best.tree_parts == "whole") {
    WalkOptions g = best;
    g.tree_parts = "trunk-crown";
    s.candidates.push_back({g});
  }
  for (std::uint32_t cluster : {64u, 128u}) {
    if (cluster == best.cluster) continue;
    WalkOptions g = best;
    g.cluster = cluster;
    s.candidates.push_back({g});
  }
  return s;
}

// Each granularity needs a scene of its own: the runs alternate per repetition, and each
// candidate's time is the median of its repetitions.
void runGranularity(LoadedScene& scene, Stage& s, std::size_t repeat, const std::string& label) {
  std::vector<LoadedScene> scenes;
  for (std::size_t i = 1; i < s.candidates.size(); ++i) {
    scenes.push_back(loadScene(s.candidates[i].options));
  }
  std::vector<std::vector<double>> ms(s.candidates.size());
  for (std::size_t r = 0; r < repeat; ++r) {
    for (std::size_t i = 0; i < s.candidates.size(); ++i) {
      std::vector<Candidate> one{s.candidates[i]};
      runOnScene(i == 0 ? scene : scenes[i - 1], one, 1, label);
      ms[i].push_back(one[0].ms);
      if (r == 0) s.candidates[i].missed = one[0].missed;
    }
  }
  for (std::size_t i = 0; i < s.candidates.size(); ++i) {
    std::sort(ms[i].begin(), ms[i].end());
    s.candidates[i].ms = ms[i][ms[i].size() / 2];
  }
  pickBest(s);
}

const WalkOptions& bestOf(const Stage& s) { return s.candidates[s.best].options; }

// The stages, each printed and in the report's "stages", and what the scene needed.
nlohmann::json reportStages(const std::vector<Stage>& stages, const nlohmann::json& needed,
                            const std::string& scene_name) {
  nlohmann::json report = nlohmann::json::array();
  for (const Stage& s : stages) {
    print(s);
    nlohmann::json js{{"stage", s.name}, {"candidates", nlohmann::json::array()}};
    for (const Candidate& c : s.candidates) {
      js["candidates"].push_back(
          {{"setting", describe(c.options)}, {"ms", c.ms}, {"missed", c.missed}});
    }
    report.push_back(std::move(js));
  }
  std::printf("what %s needed (a part pays when it is %.0f%% faster than going without):\n",
              scene_name.c_str(), 100 * kPaysMargin);
  for (const nlohmann::json& v : needed) {
    if (v["needed"].is_null()) continue;
    std::printf("  %-48s %s (%.2f vs %.2f ms)\n", v["part"].get<std::string>().c_str(),
                v["needed"].get<bool>() ? "needed" : "not needed", v["with_ms"].get<double>(),
                v["without_ms"].get<double>());
  }
  return report;
}

bool anyMissed(const std::vector<Stage>& stages) {
  for (const Stage& s : stages) {
    for (const Candidate& c : s.candidates) {
      if (c.missed > 0) return true;
    }
  }
  return false;
}

// The configuration file of --write-config: `best` as a CullerConfig, its scene section,
// and the report's summary; read back with the library's own reader.
void writeConfig(const TuneAutoOptions& o, const WalkOptions& best, const LoadedScene& scene,
                 double ms_per_frame, const nlohmann::json& needed) {
  CullerConfig config;
  const RunConfig run = runConfig(best, scene.prepared);
  config.culler = run.culler;
  config.culler.method = *run.method.method;
  config.source = best.reader;
  nlohmann::json file = nlohmann::json::parse(formatCullerConfig(config));
  file["scene"] = nlohmann::json::parse(sceneSection(best));
  file["report"] = {
      {"scene", scene.prepared.name}, {"size", o.walk.size}, {"frames", o.walk.frames},
      {"ms_per_frame", ms_per_frame}, {"needed", needed},    {"command", commandLine()}};
  std::ofstream out(o.config);
  out << file.dump(2) << "\n";
  if (!out) {
    throw Error(ErrorCode::Environment, "tune: cannot write the configuration " + o.config);
  }
  // What was written must read back as written (the library's own reader).
  (void)loadCullerConfig(o.config);
  std::printf("wrote %s (walk, bench and view take it with --config)\n", o.config.c_str());
}

}  // namespace

int runTuneAuto(const TuneAutoOptions& o) {
  gl::Context context(contextDesc(o.walk));
  LoadedScene scene = loadScene(o.walk);
  const std::string label = "tune --auto " + scene.prepared.name;
  std::vector<Stage> stages;
  // Runs a stage on the scene, keeps it, and answers its fastest candidate.
  const auto run = [&](Stage s, const char* what) {
    runOnScene(scene, s.candidates, o.repeat, label + what);
    pickBest(s);
    stages.push_back(std::move(s));
    return bestOf(stages.back());
  };

  // 1. Method, lookahead, coherence; what the scene needs is read off this stage.
  stages.push_back(methodStage(o.walk));
  runOnScene(scene, stages.back().candidates, o.repeat, label + " methods");
  const nlohmann::json needed = neededParts(stages.back());
  pickNeeded(stages.back(), needed);
  WalkOptions best = bestOf(stages.back());
  // 2. Lookahead, where batching was needed; 3. tile size, for methods with a grid;
  // 4. depth reader, for methods that read depth.
  if (const auto choice = parseMethodChoice(best.method); choice->lookahead && mayUse(needed[1])) {
    best = run(lookaheadStage(best, *choice), " lookahead");
  }
  if (infoOf(best).grid) {
    best =
        run(variantStage("3. tile size", best, &WalkOptions::tile, {8u, 16u, 32u, 64u}), " tiles");
  }
  if (infoOf(best).needs.depth) {
    best = run(variantStage("4. depth reader", best, &WalkOptions::reader,
                            {"readpixels", "pbo", "reduce"}),
               " readers");
  }
  // 5. Box granularity: a scene per choice.
  stages.push_back(granularityStage(best, o.walk.scene));
  runGranularity(scene, stages.back(), o.repeat, label + " granularity");
  best = bestOf(stages.back());

  nlohmann::json report = scene.describe();
  report["command"] = commandLine();
  report["machine"] = machineInfo(context);
  report["stages"] = reportStages(stages, needed, scene.prepared.name);
  report["needed"] = needed;
  std::printf("configuration: %s\n", describe(best).c_str());
  report["configuration"] = describe(best);
  if (!o.config.empty()) {
    writeConfig(o, best, scene, stages.back().candidates[stages.back().best].ms, needed);
  }
  if (!o.json.empty()) writeJson(o.json, report);
  if (anyMissed(stages)) {
    std::fprintf(stderr, "tune: a conservative run missed visible objects: a bug\n");
    return 1;
  }
  return 0;
}

}  // namespace logrid::samples
