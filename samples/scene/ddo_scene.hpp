// The DDO octree of a prepared scene (logrid/ddo/*.hpp): built from the renderer's mesh
// (objects are the renderer's draws; only the static ones, PreparedScene::static_objects:
// moving objects are in no octree and occlude nothing in it), or loaded from a DDO file when one
// exists for this very scene, and saved after building when a file is named.
#pragma once

#include <memory>
#include <string>

#include "logrid/ddo/build.hpp"
#include "logrid/ddo/octree.hpp"
#include "scene/prepare.hpp"

namespace logrid::samples {

struct DdoOptions {
  std::uint32_t regions = 64;
  std::uint32_t leaf_triangles = 2048;
  std::uint32_t threads = 0;  // 0: one per hardware thread
  std::string file;           // load from / save to this path; empty: build in memory only
  bool rebuild = false;       // build and overwrite `file` even if it holds a usable octree
  bool progress = true;       // progress lines on stderr
};

struct DdoScene {
  std::shared_ptr<const ddo::Octree> octree;
  ddo::BuildReport report;  // when built
  bool loaded = false;      // read from `file` instead of built
  std::string file;
  double checksum_ms = 0;  // checksumming the scene (to tie the file to it)
  double load_ms = 0;      // reading the file, when loaded
  double save_ms = 0;      // writing the file, when built and saved
  std::uint64_t file_bytes = 0;
};

// The file a scene's DDO goes to by default: next to a model file (FILE.ddo, or
// FILE+ANIMATION.ddo when an animation file moves some of its meshes, which the octree
// then leaves out); none for the procedural scenes ("") unless the caller names one.
std::string defaultDdoFile(const std::string& scene_argument, const std::string& motion_file = "");

// Builds or loads the scene's octree. Throws logrid::Error when a file exists but is
// stale, foreign or built with other parameters (delete it or pass rebuild), or cannot be
// written.
DdoScene prepareDdo(const PreparedScene& scene, const DdoOptions& options);

}  // namespace logrid::samples
