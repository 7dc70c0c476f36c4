// logrid ddo: builds (or loads) the directional discretized occluders of a scene, saves
// them to a DDO file when one is named (FILE.ddo beside a model file by default), and
// reports what the preprocessing took: time per stage, nodes, valid faces and memory.
#include <cstdio>
#include <memory>

#include "cli/commands.hpp"
#include "cli/loaded_scene.hpp"
#include "cli/machine.hpp"
#include "cli/report.hpp"

namespace logrid::samples {
namespace {

struct DdoCommandOptions {
  WalkOptions walk;
  std::string json;
};

int runDdo(const DdoCommandOptions& c) {
  WalkOptions o = c.walk;
  LoadedScene scene = loadScene(o, false, false);
  const std::uint64_t scene_rss = peakRssBytes();
  const DdoScene d = prepareDdo(scene.prepared, ddoOptions(o));
  const std::uint64_t ddo_rss = peakRssBytes();
  nlohmann::json out = scene.describe();
  out["ddo"] = describeDdo(d);
  out["peak_rss_bytes_before_ddo"] = scene_rss;
  out["peak_rss_bytes_after_ddo"] = ddo_rss;

  const ddo::Octree& octree = *d.octree;
  const ddo::BuildReport& r = d.report;
  const double nodes = double(octree.nodes().size());
  std::printf("%s: %llu triangles, %zu objects\n", scene.prepared.name.c_str(),
              (unsigned long long)scene.prepared.triangles, scene.prepared.mesh.draws.size());
  if (d.loaded) {
    std::printf("loaded %s (%llu bytes) in %.0f ms\n", d.file.c_str(),
                (unsigned long long)d.file_bytes, d.load_ms);
  } else {
    std::printf(
        "built with %u threads in %.1f s: octree %.1f s, shared edges %.1f s, segment index %.1f "
        "s, faces %.1f s\n",
        r.threads, r.total_ms / 1000, r.octree_ms / 1000, r.topology_ms / 1000, r.index_ms / 1000,
        r.faces_ms / 1000);
    std::printf(
        "%llu regions tested, %llu valid; %llu pieces followed, %llu abandoned; "
        "%llu regions with only grazing test segments\n",
        (unsigned long long)r.regions_tested, (unsigned long long)r.regions_valid,
        (unsigned long long)r.pieces_followed, (unsigned long long)r.pieces_abandoned,
        (unsigned long long)r.regions_degenerate);
    if (!d.file.empty()) {
      std::printf("saved %s (%llu bytes) in %.0f ms\n", d.file.c_str(),
                  (unsigned long long)d.file_bytes, d.save_ms);
    }
  }
  std::uint64_t valid_faces = 0;
  for (std::uint64_t m : octree.masks()) valid_faces += m != 0;
  std::printf("%zu nodes (depth %u), %llu of %zu faces valid from some region; %u regions a face\n",
              octree.nodes().size(), octree.depth(), (unsigned long long)valid_faces,
              octree.nodes().size() * ddo::kFaces, octree.params().regions);
  std::printf(
      "memory: masks %.1f MiB (%.0f bytes a node, %u bytes a face on file), octree in all "
      "%.1f MiB (%.0f bytes a node); peak resident %.0f MiB before the DDO, %.0f MiB "
      "after\n",
      double(octree.maskBytes()) / (1 << 20), double(octree.maskBytes()) / nodes,
      octree.params().regions / 8, double(octree.memoryBytes()) / (1 << 20),
      double(octree.memoryBytes()) / nodes, double(scene_rss) / (1 << 20),
      double(ddo_rss) / (1 << 20));
  if (!c.json.empty()) writeJson(c.json, out);
  return 0;
}

}  // namespace

void addDdoCommand(CLI::App& app) {
  auto options = std::make_shared<DdoCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "ddo", "preprocess a scene's directional discretized occluders and report the cost");
  addSceneOptions(*cmd, options->walk);
  cmd->add_option("--json", options->json, "write the report as JSON");
  cmd->final_callback([options] { throw CLI::RuntimeError(runDdo(*options)); });
}

}  // namespace logrid::samples
