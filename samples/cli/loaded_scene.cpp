#include "cli/loaded_scene.hpp"

#include <chrono>

#include "cli/machine.hpp"
#include "cli/values.hpp"
#include "logrid/elapsed.hpp"
#include "scene/generators.hpp"
#include "scene/loader.hpp"
#include "scene/movers.hpp"

namespace logrid::samples {

nlohmann::json LoadedScene::describe() const {
  const PreparedScene& p = prepared;
  return {{"scene", p.name},
          {"scene_triangles", p.triangles},
          {"scene_objects", p.mesh.draws.size()},
          {"source_objects", p.source_objects},
          {"objects", p.objectCount()},
          {"clusters", p.clustered() ? p.mesh.draws.size() : 0},
          {"cluster_ms", p.cluster_ms},
          {"hierarchy_nodes", p.hierarchy.nodes().size()},
          {"hierarchy_depth", p.hierarchy.depth()},
          {"generate_ms", generate_ms},
          {"bvh_build_ms", p.bvh_build_ms},
          {"prepare_ms", p.prepare_ms},
          {"cpu_bytes", p.memoryBytes()},
          {"gpu_bytes", renderer ? renderer->gpuBytes() : 0},
          {"peak_rss_bytes", peak_rss_bytes},
          {"prepare_peak_rss_bytes", prepare_peak_rss_bytes},
          {"bytes_per_triangle", p.triangles ? double(peak_rss_bytes) / double(p.triangles) : 0.0},
          {"ddo", ddo ? describeDdo(*ddo) : nlohmann::json()}};
}

WalkOptions optionsForScene(const WalkOptions& base, const std::string& scene, double forest_scale,
                            double city_scale) {
  WalkOptions o = base;
  o.scene = scene;
  if (scene == "forest" && forest_scale > 0) o.scale = forest_scale;
  if (scene == "city" && city_scale > 0) o.scale = city_scale;
  return o;
}

DdoOptions ddoOptions(const WalkOptions& o) {
  DdoOptions d;
  d.regions = o.ddo_regions;
  d.leaf_triangles = o.ddo_leaf;
  d.threads = o.ddo_threads;
  d.rebuild = o.ddo_rebuild;
  d.file = o.ddo_file == "auto"   ? defaultDdoFile(o.scene, o.motion_file)
           : o.ddo_file == "none" ? ""
                                  : o.ddo_file;
  return d;
}

nlohmann::json describeDdo(const DdoScene& d) {
  const ddo::Octree& o = *d.octree;
  const ddo::BuildReport& r = d.report;
  const double nodes = double(o.nodes().size());
  std::uint64_t valid_faces = 0;
  for (std::uint64_t m : o.masks()) valid_faces += m != 0;
  return {{"file", d.file},
          {"loaded", d.loaded},
          {"regions", o.params().regions},
          {"leaf_triangles", o.params().leaf_triangles},
          {"nodes", o.nodes().size()},
          {"depth", o.depth()},
          {"faces", o.nodes().size() * ddo::kFaces},
          {"valid_faces", valid_faces},
          {"mask_bytes", o.maskBytes()},
          {"mask_bytes_per_node", nodes > 0 ? double(o.maskBytes()) / nodes : 0.0},
          {"file_mask_bytes_per_face", o.params().regions / 8},
          {"octree_bytes", o.memoryBytes()},
          {"octree_bytes_per_node", nodes > 0 ? double(o.memoryBytes()) / nodes : 0.0},
          {"file_bytes", d.file_bytes},
          {"checksum_ms", d.checksum_ms},
          {"load_ms", d.load_ms},
          {"save_ms", d.save_ms},
          {"build",
           {{"threads", r.threads},
            {"octree_ms", r.octree_ms},
            {"topology_ms", r.topology_ms},
            {"index_ms", r.index_ms},
            {"faces_ms", r.faces_ms},
            {"total_ms", r.total_ms},
            {"leaves", r.leaves},
            {"faces_nothing_behind", r.faces_nothing_behind},
            {"faces_valid", r.faces_valid},
            {"regions_tested", r.regions_tested},
            {"regions_valid", r.regions_valid},
            {"regions_degenerate", r.regions_degenerate},
            {"pieces_followed", r.pieces_followed},
            {"pieces_abandoned", r.pieces_abandoned},
            {"pieces_open", r.pieces_open},
            {"corner_misses", r.corner_misses},
            {"pieces_closed_even", r.pieces_closed_even},
            {"piece_triangles", r.piece_triangles},
            {"temporary_bytes", r.temporary_bytes}}}};
}

LoadedScene loadScene(const WalkOptions& o, bool upload, bool with_ddo) {
  LoadedScene out;
  const auto start = std::chrono::steady_clock::now();
  Scene scene;
  if (o.scene == "forest") {
    scene = makeForest({o.scale, o.seed, parseTreeParts(o.tree_parts)});
  } else if (o.scene == "city") {
    scene = makeCity({o.scale, o.seed});
  } else if (o.scene == "office") {
    scene = makeOffice({o.scale, o.seed});
  } else {
    scene = loadSceneFile(o.scene);
  }
  if (!o.path_file.empty()) scene.path = CameraPath::fromJsonFile(o.path_file);
  if (!o.motion_file.empty()) animateMeshes(scene, o.motion_file);
  addMovers(scene, o.movers, o.seed);
  out.generate_ms = msSince(start);
  bvh::BuildArgs args = defaultBuildArgs(scene);
  if (o.leaf) args.max_leaf_size = o.leaf;
  ClusterOptions clusters;
  clusters.triangles = o.cluster;
  clusters.method = parseClusterMethod(o.cluster_method);
  out.prepared = prepareScene(std::move(scene), args, clusters);
  out.prepare_peak_rss_bytes = peakRssBytes();
  if (with_ddo) {
    out.ddo = prepareDdo(out.prepared, ddoOptions(o));
    out.prepared.ddo = out.ddo->octree;
  }
  if (upload) out.renderer = std::make_unique<gl::MeshRenderer>(out.prepared.mesh);
  out.peak_rss_bytes = peakRssBytes();
  return out;
}

}  // namespace logrid::samples
