#include "cli/cluster_sweep.hpp"

#include <algorithm>
#include <memory>

#include "cli/common.hpp"
#include "cli/report.hpp"
#include "cli/values.hpp"
#include "logrid/error.hpp"

namespace logrid::samples {
namespace {

std::string granularityName(std::uint32_t cluster) {
  return cluster ? std::to_string(cluster) + "-triangle clusters" : "whole objects";
}

struct Row {
  std::uint32_t cluster = 0;
  std::string method;
  double ms = 0, spread = 0;
  FrameAverages f;
  bool oracle = false;
  bool conservative = true;
  // What the row is measured against: the oracle of its own granularity (the cluster
  // oracle) and of whole objects (the object oracle); nullptr where not run.
  const Row* cluster_oracle = nullptr;
  const Row* object_oracle = nullptr;
};

std::string versus(double value, const Row* base, double Row::*field) {
  return base && base->*field > 0 ? formatRatio(value, base->*field, "×") : "–";
}

void writeRows(std::ostream& md, const std::vector<Row>& rows) {
  writeTable<Row>(
      md,
      {{"granularity", "---", [](const Row& r) { return granularityName(r.cluster); }},
       {"method", "---", [](const Row& r) { return r.method; }},
       {"ms/frame", "--:", [](const Row& r) { return formatFixed(r.ms); }},
       {"spread", "--:", [](const Row& r) { return formatFixed(100 * r.spread, 0) + "%"; }},
       {"× cluster oracle",
        "--:", [](const Row& r) { return versus(r.ms, r.cluster_oracle, &Row::ms); }},
       {"× object oracle",
        "--:", [](const Row& r) { return versus(r.ms, r.object_oracle, &Row::ms); }},
       {"ids drawn", "--:", [](const Row& r) { return grouped(r.f.objects); }},
       {"objects drawn",
        "--:", [](const Row& r) { return grouped(r.f.cluster_objects.value_or(r.f.objects)); }},
       {"triangles", "--:", [](const Row& r) { return grouped(r.f.triangles); }},
       {"× cluster oracle's", "--:",
        [](const Row& r) {
          return r.cluster_oracle && r.cluster_oracle->f.triangles > 0
                     ? formatRatio(r.f.triangles, r.cluster_oracle->f.triangles, "×")
                     : "–";
        }},
       {"draw calls", "--:", [](const Row& r) { return formatFixed(r.f.draw_calls, 1); }},
       {"pixels read", "--:", [](const Row& r) { return grouped(r.f.pixels_read); }},
       {"flushes", "--:", [](const Row& r) { return formatFixed(r.f.flushes, 1); }},
       {"missed",
        "--:", [](const Row& r) { return r.f.verified ? std::to_string(r.f.missed) : "–"; }}},
      rows);
}

// Per granularity: clusters, what preparing took, and the bytes per triangle held.
void writeGranularities(std::ostream& md, const std::vector<std::uint32_t>& clusters,
                        const std::vector<std::unique_ptr<LoadedScene>>& scenes) {
  md << "\n| granularity | ids (objects or clusters) | clusters built in | hierarchy built in "
        "| prepared in | CPU bytes/triangle | GPU bytes/triangle |\n"
        "|---|--:|--:|--:|--:|--:|--:|\n";
  for (std::size_t g = 0; g < clusters.size(); ++g) {
    const PreparedScene& p = scenes[g]->prepared;
    const double triangles = std::max(1.0, double(p.triangles));
    md << "| " << granularityName(clusters[g]) << " | " << grouped(double(p.mesh.draws.size()))
       << " | " << (p.clustered() ? formatFixed(p.cluster_ms, 0) + " ms" : "–") << " | "
       << formatFixed(p.bvh_build_ms, 0) << " ms | " << formatFixed(p.prepare_ms, 0) << " ms | "
       << formatFixed(double(p.memoryBytes()) / triangles, 1) << " | "
       << formatFixed(double(scenes[g]->renderer->gpuBytes()) / triangles, 1) << " |\n";
  }
}

nlohmann::json rowJson(const Row& r) {
  nlohmann::json j = {{"cluster", r.cluster},
                      {"method", r.method},
                      {"ms", r.ms},
                      {"spread", r.spread},
                      {"ids_drawn", r.f.objects},
                      {"objects_drawn", r.f.cluster_objects.value_or(r.f.objects)},
                      {"triangles", r.f.triangles},
                      {"draw_calls", r.f.draw_calls},
                      {"pixels_read", r.f.pixels_read},
                      {"flushes", r.f.flushes}};
  if (r.f.verified) j["missed"] = r.f.missed;
  if (r.cluster_oracle) j["vs_cluster_oracle_ms"] = r.ms / r.cluster_oracle->ms;
  if (r.object_oracle) j["vs_object_oracle_ms"] = r.ms / r.object_oracle->ms;
  return j;
}

constexpr const char* kIntro =
    "One scene prepared at several granularities (whole objects, and each object split "
    "into clusters of at most N triangles by meshoptimizer, each culled on its own box), "
    "every method at every granularity on the same frames, all interleaved frame by "
    "frame. A clustered scene's ids are its clusters: `ids drawn` counts them, `objects "
    "drawn` the objects they belong to. The cluster oracle draws exactly the visible "
    "clusters (found by an untimed ID pass of cluster ids: a culled visible cluster is a "
    "miss even where another cluster of its object was drawn); the object oracle "
    "(whole objects' oracle) draws every visible object whole. Batches are drawn with "
    "glMultiDrawElementsBaseVertex, an object's consecutive clusters as one range.\n";

}  // namespace

int runClusterSweep(const ExperimentOptions& options, const std::vector<std::string>& methods,
                    const std::vector<std::uint32_t>& clusters) {
  if (methods.empty() || clusters.empty()) {
    throw Error(ErrorCode::InvalidArgument, "bench --clusters: needs --methods and a size");
  }
  for (const std::string& m : methods) {
    std::string problem;
    if (!parseMethodChoice(m, &problem)) {
      throw Error(ErrorCode::InvalidArgument, "bench --clusters: " + problem);
    }
  }
  Experiment e(options, "bench --clusters", "logrid: culling clusters", kIntro);
  e.report()["cells"] = nlohmann::json::array();
  std::vector<Variant> variants;
  for (const std::string& m : methods)
    variants.push_back({m, [m](WalkOptions& o) { o.method = m; }});
  bool missed = false;
  for (const std::string& scene_name : options.scenes) {
    std::vector<std::unique_ptr<LoadedScene>> scenes;
    for (std::uint32_t cluster : clusters) {
      WalkOptions so = e.sceneOptions(scene_name);
      so.cluster = cluster;
      scenes.push_back(std::make_unique<LoadedScene>(e.load(so, variants)));
    }
    const std::string name = scenes.front()->prepared.name;
    e.md() << "\n## " << name << "\n";
    writeGranularities(e.md(), clusters, scenes);
    for (const std::string& size : options.sizes) {
      std::vector<SceneConfig> configs;
      std::vector<Row> rows;
      for (std::size_t g = 0; g < clusters.size(); ++g) {
        for (const Variant& v : variants) {
          WalkOptions o = e.sceneOptions(scene_name);
          o.cluster = clusters[g];
          o.size = size;
          o.verify = options.verify;
          v.apply(o);
          configs.push_back(
              {&scenes[g]->prepared, scenes[g]->renderer.get(), runConfig(o, scenes[g]->prepared)});
          Row r;
          r.cluster = clusters[g];
          r.method = v.label;
          rows.push_back(r);
        }
      }
      const std::vector<ConfigResult> results =
          runInterleaved(configs, options.repeat, "clusters " + name + " " + size, options.warmup);
      for (std::size_t i = 0; i < rows.size(); ++i) {
        const RunConfig& c = results[i].config;
        rows[i].ms = results[i].avg_ms();
        rows[i].spread = results[i].spread();
        rows[i].f = averageFrames(results[i].records);
        rows[i].oracle = c.method.oracle();
        rows[i].conservative = c.culler.approximation.exact() && c.culler.budget_ms == 0;
        missed = missed || (rows[i].conservative && rows[i].f.verified && rows[i].f.missed > 0);
      }
      for (Row& r : rows) {
        for (const Row& o : rows) {
          if (!o.oracle) continue;
          if (o.cluster == r.cluster) r.cluster_oracle = &o;
          if (o.cluster == 0) r.object_oracle = &o;
        }
      }
      const RunConfig& first = results.front().config;
      e.md() << "\n### " << name << " " << size << "\n\n"
             << framesAlong(first.frames, first.time_step) << ", " << options.repeat
             << " interleaved repetitions (ms/frame: average over frames of the per-frame "
                "median).\n\n";
      writeRows(e.md(), rows);
      nlohmann::json cell = {{"scene", name},
                             {"size", size},
                             {"granularities", nlohmann::json::array()},
                             {"rows", nlohmann::json::array()}};
      for (const auto& s : scenes) cell["granularities"].push_back(s->describe());
      for (const Row& r : rows) cell["rows"].push_back(rowJson(r));
      e.report()["cells"].push_back(cell);
    }
  }
  return e.finish(missed ? "bench --clusters: a conservative method missed visible clusters "
                           "(see 'missed'); that is a bug, please report it with the command "
                           "line"
                         : "");
}

}  // namespace logrid::samples
