// DDO files (DDO §3.1: "saved to a DDO file which can be read and used at a later
// time"): the octree and every face's bitmask, tied to the scene they were built from.
//
// Layout (little-endian): an 8-byte magic "logrdDDO", the format version, the scene's
// checksum (mesh.hpp), triangle and object counts, the build parameters, the nodes, the
// leaves' object lists, the masks (regions / 8 bytes per face), and a checksum of all
// that precedes it. Written to a temporary file and renamed, so a crash never leaves a
// half-written file under the final name.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "logrid/ddo/octree.hpp"
#include "logrid/error.hpp"

namespace logrid::ddo {

inline constexpr std::uint32_t kFileVersion = 1;

// What the scene and the caller require of a file.
struct FileExpectation {
  std::uint64_t scene_checksum = 0;
  std::uint64_t triangles = 0;
  std::uint64_t objects = 0;
  std::uint32_t regions = 0;         // 0: any
  std::uint32_t leaf_triangles = 0;  // 0: any
};

// The checksum a file ends with, of the `bytes` bytes before it (FNV-1a over 8-byte
// words, then the remaining bytes).
std::uint64_t payloadChecksum(const unsigned char* data, std::size_t bytes);

// Saving and loading come in both forms (logrid/error.hpp): trySaveOctree() and
// tryLoadOctree() return the error, saveOctree() and loadOctree() throw it as
// logrid::Error.
//
// Fails with ErrorCode::Environment when the file cannot be written (naming the path).
Status trySaveOctree(const Octree& octree, const FileExpectation& scene, const std::string& path);
void saveOctree(const Octree& octree, const FileExpectation& scene, const std::string& path);

// Fails naming the path and what to do: ErrorCode::Environment when it cannot be read;
// ErrorCode::BadInput when it is not a DDO file, has another format version, is
// truncated or corrupt, was built for another scene (stale: the scene's checksum or
// counts differ) or with other parameters than `expect` asks for, or describes an
// inconsistent octree.
Result<Octree> tryLoadOctree(const std::string& path, const FileExpectation& expect);
Octree loadOctree(const std::string& path, const FileExpectation& expect);

#if LOGRID_HAS_EXCEPTIONS
inline void saveOctree(const Octree& octree, const FileExpectation& scene,
                       const std::string& path) {
  logrid::orThrow(trySaveOctree(octree, scene, path));
}
inline Octree loadOctree(const std::string& path, const FileExpectation& expect) {
  return logrid::orThrow(tryLoadOctree(path, expect));
}
#endif

}  // namespace logrid::ddo
