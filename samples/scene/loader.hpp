// Scenes from model files through assimp: glTF 2.0, OBJ, PLY, STL, FBX, ... Each mesh
// instance (a node's mesh with the node's transform applied) becomes one object; a
// default camera path orbits the model's bounds.
//
// What assimp reads, loads: the loader refuses beforehand only what makes assimp 5.2
// hang, crash or silently import wrong geometry (loader_ply.cpp and loader_gltf.cpp say
// which files, found by experiment), and reports through LoadOptions::warn where a file
// bends its format in a way assimp reads correctly (an old exporter's free-text header
// line, extra values on a line, ...).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "scene/scene.hpp"

namespace logrid::samples {

struct LoadOptions {
  // Files larger than this are refused before parsing (bytes).
  std::uint64_t max_file_bytes = 2ull << 30;
  // Scenes with more triangles than this are refused after parsing.
  std::uint64_t max_triangles = 200'000'000;
  // Called once for each way the file bends its format (the message names the file and
  // says what assimp does with it). Empty: the warning goes to stderr as
  // "logrid: warning: <message>".
  std::function<void(const std::string& message)> warn;
};

// Throws logrid::Error with the file name and what failed: ErrorCode::Environment for a
// missing or unreadable file, ErrorCode::BadInput for an unknown format, a file assimp
// cannot read or would read wrongly (truncated, counts that disagree with the data,
// ...), NaN/infinite vertices, indices out of range, or a scene without a single
// triangle; ErrorCode::Unsupported when built without assimp.
Scene loadSceneFile(const std::string& path, const LoadOptions& options = {});

// True when the build has assimp.
bool sceneFilesSupported();

}  // namespace logrid::samples
