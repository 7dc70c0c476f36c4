#include "scene/ddo_scene.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "logrid/ddo/file.hpp"
#include "logrid/elapsed.hpp"
#include "logrid/error.hpp"

namespace logrid::samples {

std::string defaultDdoFile(const std::string& scene_argument, const std::string& motion_file) {
  if (scene_argument == "forest" || scene_argument == "city" || scene_argument == "office" ||
      scene_argument.empty()) {
    return "";
  }
  if (motion_file.empty()) return scene_argument + ".ddo";
  // The meshes an animation file moves are not in the octree: another static scene.
  return scene_argument + "+" + std::filesystem::path(motion_file).stem().string() + ".ddo";
}

DdoScene prepareDdo(const PreparedScene& scene, const DdoOptions& options) {
  DdoScene out;
  out.file = options.file;
  // The renderer's mesh as one triangle list: vertex indices made global, objects = draws.
  // Only the static objects [0, static_objects): the occluders hold for the static scene
  // (a mover's draw holds its geometry in its own frame, placed by a transform per frame).
  const gl::RenderMesh& mesh = scene.mesh;
  std::vector<std::uint32_t> indices;
  indices.reserve(mesh.triangleCount() * 3);
  std::vector<std::uint32_t> object_first;
  object_first.reserve(std::size_t(scene.static_objects) + 1);
  for (std::uint32_t o = 0; o < scene.static_objects && o < mesh.draws.size(); ++o) {
    const gl::RenderMesh::Draw& d = mesh.draws[o];
    object_first.push_back(std::uint32_t(indices.size() / 3));
    for (std::uint32_t i = d.first_index; i < d.first_index + d.index_count; ++i) {
      const std::uint32_t local = mesh.indices16.empty() ? mesh.indices32[i] : mesh.indices16[i];
      indices.push_back(std::uint32_t(d.base_vertex) + local);
    }
  }
  object_first.push_back(std::uint32_t(indices.size() / 3));
  const ddo::SceneMesh view(mesh.positions, indices, object_first);

  auto start = std::chrono::steady_clock::now();
  ddo::FileExpectation expect;
  expect.scene_checksum = ddo::sceneChecksum(view);
  expect.triangles = indices.size() / 3;
  expect.objects = object_first.size() - 1;
  expect.regions = options.regions;
  expect.leaf_triangles = options.leaf_triangles;
  out.checksum_ms = msSince(start);

  if (!options.file.empty() && !options.rebuild && std::filesystem::exists(options.file)) {
    start = std::chrono::steady_clock::now();
    out.octree = std::make_shared<const ddo::Octree>(ddo::loadOctree(options.file, expect));
    out.load_ms = msSince(start);
    out.loaded = true;
    out.file_bytes = std::filesystem::file_size(options.file);
    return out;
  }

  ddo::BuildArgs args;
  args.regions = options.regions;
  args.leaf_triangles = options.leaf_triangles;
  args.threads = options.threads;
  const bool tty = isatty(STDERR_FILENO) != 0;
  int last_tenth = -1;
  auto progress = [&](const ddo::BuildProgress& p) {
    if (!options.progress) return;
    const int tenth = p.total ? int(p.done * 10 / p.total) : 0;
    if (tty) {
      std::fprintf(stderr, "\rddo %s: %s %llu/%llu   ", scene.name.c_str(), p.stage,
                   (unsigned long long)p.done, (unsigned long long)p.total);
      if (p.done == p.total && std::string(p.stage) == "faces") std::fprintf(stderr, "\n");
    } else if (std::string(p.stage) != "faces" ? p.done == 0 : tenth != last_tenth) {
      last_tenth = tenth;
      std::fprintf(stderr, "ddo %s: %s %llu/%llu\n", scene.name.c_str(), p.stage,
                   (unsigned long long)p.done, (unsigned long long)p.total);
    }
  };
  out.octree =
      std::make_shared<const ddo::Octree>(ddo::buildOctree(view, args, progress, &out.report));
  if (!options.file.empty()) {
    start = std::chrono::steady_clock::now();
    ddo::saveOctree(*out.octree, expect, options.file);
    out.save_ms = msSince(start);
    out.file_bytes = std::filesystem::file_size(options.file);
  }
  return out;
}

}  // namespace logrid::samples
