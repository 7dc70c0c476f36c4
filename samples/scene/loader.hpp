// Scenes from model files through assimp: glTF 2.0, OBJ, PLY, STL, FBX, ... Each mesh
// instance (a node's mesh with the node's transform applied) becomes one object; a
// default camera path orbits the model's bounds.
#pragma once

#include <string>

#include "scene/scene.hpp"

namespace logrid::samples {

struct LoadOptions {
  // Files larger than this are refused before parsing (bytes).
  std::uint64_t max_file_bytes = 2ull << 30;
  // Scenes with more triangles than this are refused after parsing.
  std::uint64_t max_triangles = 200'000'000;
};

// Throws logrid::Error with the file name and what failed: ErrorCode::Environment for a
// missing or unreadable file, ErrorCode::BadInput for an unknown format, a truncated or
// malformed file, NaN/infinite vertices, indices out of range, or a scene without a
// single triangle; ErrorCode::Unsupported when built without assimp.
Scene loadSceneFile(const std::string& path, const LoadOptions& options = {});

// True when the build has assimp.
bool sceneFilesSupported();

}  // namespace logrid::samples
