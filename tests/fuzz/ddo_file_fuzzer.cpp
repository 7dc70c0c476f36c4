// libFuzzer target: DDO files through tryLoadOctree (logrid/ddo/file.hpp). The first byte
// says how far a mutated file may get: bit 0 recomputes the trailing checksum, bit 1
// takes the expected scene (checksum, triangle and object counts) from the file's own
// header, so that mutations reach the parameter and structure checks behind them instead
// of stopping at "corrupt" or "stale". The rest is the file. Every input must either be
// refused with ErrorCode::BadInput naming the file (and the throwing form, loadOctree,
// must throw the same code and message), or load into an octree that the
// run time can walk without checks (children after their parent and inside the node
// list, object ranges inside the object list, object ids inside the scene, one mask per
// face) and that saves and loads back unchanged.
#include <unistd.h>

#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "fuzz_check.hpp"
#include "logrid/ddo/file.hpp"
#include "logrid/error.hpp"

namespace {

namespace fs = std::filesystem;

constexpr std::size_t kHeader = 8 + 4;  // magic, version; then checksum, triangles, objects

void write(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  LOGRID_FUZZ_CHECK(out.good(), "cannot write the input to %s", path.c_str());
}

void checkWalkable(const logrid::ddo::Octree& o, const logrid::ddo::FileExpectation& e) {
  const auto& nodes = o.nodes();
  LOGRID_FUZZ_CHECK(!nodes.empty(), "loaded an octree without nodes");
  LOGRID_FUZZ_CHECK(o.masks().size() == nodes.size() * logrid::ddo::kFaces,
                    "%zu masks for %zu nodes", o.masks().size(), nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const logrid::ddo::OctreeNode& n = nodes[i];
    if (!n.leaf()) {
      LOGRID_FUZZ_CHECK(n.first_child > i && n.first_child + n.childCount() <= nodes.size(),
                        "node %zu: children %u+%u outside the %zu nodes", i, n.first_child,
                        n.childCount(), nodes.size());
    }
    LOGRID_FUZZ_CHECK(std::uint64_t(n.first_object) + n.object_count <= o.objects().size(),
                      "node %zu: objects outside the list", i);
    for (int k = 0; k < 8; ++k) {
      const std::uint32_t c = o.child(std::uint32_t(i), k);
      LOGRID_FUZZ_CHECK(c == logrid::ddo::Octree::kNone || c < nodes.size(),
                        "node %zu octant %d: child %u", i, k, c);
    }
  }
  for (logrid::ObjectId id : o.objects()) {
    LOGRID_FUZZ_CHECK(id < e.objects, "object %u of a scene of %llu", id,
                      (unsigned long long)e.objects);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static logrid::fuzz::ScratchDir scratch("ddo_file_fuzzer");
  if (size == 0) return 0;
  const std::uint8_t mode = data[0];
  std::vector<unsigned char> bytes(data + 1, data + size);
  logrid::ddo::FileExpectation expect;
  if ((mode & 2) && bytes.size() >= kHeader + 24) {
    std::memcpy(&expect.scene_checksum, bytes.data() + kHeader, 8);
    std::memcpy(&expect.triangles, bytes.data() + kHeader + 8, 8);
    std::memcpy(&expect.objects, bytes.data() + kHeader + 16, 8);
  }
  if ((mode & 1) && bytes.size() >= 8) {
    const std::uint64_t sum = logrid::ddo::payloadChecksum(bytes.data(), bytes.size() - 8);
    std::memcpy(bytes.data() + bytes.size() - 8, &sum, 8);
  }
  const std::string path = (scratch.dir / "input.ddo").string();
  write(path, bytes);
  logrid::Result<logrid::ddo::Octree> loaded = logrid::ddo::tryLoadOctree(path, expect);
#if LOGRID_HAS_EXCEPTIONS
  // The throwing form refuses what the result form refuses, with the same code and message.
  try {
    (void)logrid::ddo::loadOctree(path, expect);
    LOGRID_FUZZ_CHECK(loaded.ok(), "loadOctree accepted what tryLoadOctree refused: %s",
                      loaded.status().message().c_str());
  } catch (const logrid::Error& e) {
    LOGRID_FUZZ_CHECK(
        !loaded.ok() && e.code() == loaded.status().code() && e.what() == loaded.status().message(),
        "loadOctree threw '%s' where tryLoadOctree gave '%s'", e.what(),
        loaded.status().message().c_str());
  }
#endif
  if (!loaded) {
    const logrid::Status& e = loaded.status();
    LOGRID_FUZZ_CHECK(e.code() == logrid::ErrorCode::BadInput, "unexpected error code %d: %s",
                      int(e.code()), e.message().c_str());
    LOGRID_FUZZ_CHECK(e.message().find(path) != std::string::npos,
                      "the error does not name the file: %s", e.message().c_str());
    return 0;
  }
  const logrid::ddo::Octree& octree = loaded.value();
  checkWalkable(octree, expect);
  // What loads saves and loads back unchanged.
  const std::string again = (scratch.dir / "again.ddo").string();
  const logrid::Status saved = logrid::ddo::trySaveOctree(octree, expect, again);
  LOGRID_FUZZ_CHECK(saved.ok(), "saving a loaded octree failed: %s", saved.message().c_str());
  const logrid::Result<logrid::ddo::Octree> reloaded = logrid::ddo::tryLoadOctree(again, expect);
  LOGRID_FUZZ_CHECK(reloaded.ok(), "a saved octree does not load: %s",
                    reloaded.status().message().c_str());
  const logrid::ddo::Octree& back = reloaded.value();
  LOGRID_FUZZ_CHECK(back.nodes().size() == octree.nodes().size() &&
                        back.objects() == octree.objects() && back.masks() == octree.masks(),
                    "the octree changed on a save and load");
  return 0;
}
