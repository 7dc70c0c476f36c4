// The parts of the scene loader (loader.hpp), one concern a file:
//   loader.cpp               the import: file checks, which importer may read the file,
//                            what else assimp may open, parsing, post-processing, errors
//   loader_ply.cpp           PLY files checked before assimp reads them
//   loader_gltf.cpp          glTF files checked before assimp reads them
//   loader_assimp_scene.cpp  what assimp made, checked and turned into a Scene
// Internal to the samples' scene library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

#include "logrid/error.hpp"
#include "scene/loader.hpp"
#include "scene/scene.hpp"

struct aiScene;

namespace logrid::samples::load {

// Deeper node graphs than this are refused. Real files nest a few dozen levels; a
// deeper graph is almost certainly built to exhaust a recursive walker.
inline constexpr std::size_t kMaxNodeDepth = 1000;
// Mesh instances (= scene objects) and nodes visited. Each instance costs a 4x4 double
// matrix here and assimp already spent ~1 KiB per node, so these bound memory long
// before max_triangles would.
inline constexpr std::size_t kMaxInstances = std::size_t{1} << 20;
inline constexpr std::size_t kMaxNodes = std::size_t{1} << 22;

// Throws logrid::Error(code, "<path>: <what>").
[[noreturn]] void fail(ErrorCode code, const std::string& path, const std::string& what);

std::string lowerCase(std::string s);

// Receives one message per way a file bends its format, without the file name.
using Warn = std::function<void(const std::string& message)>;

// Throws logrid::Error(BadInput) for a PLY file that assimp 5.2 would hang or crash on,
// or read into wrong geometry; warns for what it reads correctly although the file bends
// the format. Files not named .ply are left alone.
void checkPly(const std::string& path, const Warn& warn);

// Throws logrid::Error(BadInput) for a glTF file (.gltf or .glb) that would make assimp
// 5.2 overflow its stack or exhaust memory. Other files are left alone.
void checkGltf(const std::string& path);

// What the importer made, before assimp's post-processing runs on it: throws
// logrid::Error(BadInput) for what the post-processing would crash on or mis-handle
// (missing arrays, empty faces, indices out of range, NaN positions, broken node
// graphs) and for a file without a single triangle.
void checkRawScene(const std::string& path, const aiScene& raw);

// The post-processed scene as a Scene: one object per mesh instance with triangles,
// transformed to world space, centred on a local origin, framed by a default orbit.
Scene sceneFromAssimp(const std::string& path, const aiScene& ai, const LoadOptions& options);

}  // namespace logrid::samples::load
