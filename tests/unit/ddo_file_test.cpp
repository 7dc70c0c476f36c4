// DDO files: a round trip keeps every node and mask; a stale, foreign, truncated,
// corrupt or otherwise-built file is refused with a message that says what to do.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>

#include "ddo_scenes.hpp"
#include "expect_error.hpp"
#include "expect_status.hpp"
#include "logrid/ddo/build.hpp"
#include "logrid/ddo/file.hpp"

namespace logrid {
namespace {

using test::TriangleScene;

struct TempPath {
  std::string path;
  explicit TempPath(const std::string& name)
      : path(testing::TempDir() + "logrid_ddo_" + std::to_string(getpid()) + "_" + name) {}
  ~TempPath() { std::remove(path.c_str()); }
};

TriangleScene scene() {
  TriangleScene s;
  std::mt19937 rng(2);
  TriangleScene::WallOptions o;
  o.n = 6;
  s.wall(2, 0.3, -5, 5, -5, 5, o);
  s.clutter(rng, 80, -6, 6, 0.4);
  return s;
}

ddo::FileExpectation expectationFor(const TriangleScene& s) {
  ddo::FileExpectation e;
  e.scene_checksum = ddo::sceneChecksum(s.mesh());
  e.triangles = s.indices.size() / 3;
  e.objects = s.object_first.size() - 1;
  return e;
}

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeAll(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

TEST(DdoFile, RoundTripKeepsTheOctreeAndItsMasks) {
  const TriangleScene s = scene();
  for (std::uint32_t regions : {64u, 32u}) {
    ddo::BuildArgs args;
    args.leaf_triangles = 8;
    args.regions = regions;
    args.threads = 1;
    const ddo::Octree built = ddo::buildOctree(s.mesh(), args);
    TempPath file("roundtrip.ddo");
    ddo::saveOctree(built, expectationFor(s), file.path);
    const ddo::Octree loaded = ddo::loadOctree(file.path, expectationFor(s));
    ASSERT_EQ(loaded.nodes().size(), built.nodes().size());
    EXPECT_EQ(loaded.objects(), built.objects());
    EXPECT_EQ(loaded.masks(), built.masks());
    EXPECT_EQ(loaded.params().root_side, built.params().root_side);
    EXPECT_EQ(loaded.params().regions, regions);
    std::uint64_t valid = 0;
    for (std::uint64_t m : loaded.masks()) valid += m != 0;
    EXPECT_GT(valid, 0u) << "nothing to compare: no face is valid";
    for (std::size_t n = 0; n < built.nodes().size(); ++n) {
      const ddo::OctreeNode& a = built.nodes()[n];
      const ddo::OctreeNode& b = loaded.nodes()[n];
      EXPECT_EQ(a.first_child, b.first_child);
      EXPECT_EQ(a.child_mask, b.child_mask);
      EXPECT_EQ(a.level, b.level);
      EXPECT_EQ(a.bounds.max.y, b.bounds.max.y);
      EXPECT_EQ(a.object_count, b.object_count);
    }
    // 32 regions take 4 bytes a face on disk, 64 take 8.
    const std::size_t size = readAll(file.path).size();
    EXPECT_GE(size, built.nodes().size() * 6 * (regions / 8));
  }
}

// A file whose leaves hold no objects (an octree of one empty root) has an empty object
// list: the reader copies zero bytes into an empty vector, whose data() may be null, which
// memcpy's contract forbids (UndefinedBehaviorSanitizer, as in scripts/sanitize.sh, reports
// it unless the reader skips empty copies; first seen when fuzzing the reader).
TEST(DdoFile, AnOctreeWithoutObjectsRoundTrips) {
  ddo::OctreeParams params;
  params.regions = 32;
  std::vector<ddo::OctreeNode> nodes(1);
  nodes[0].bounds = {{0, 0, 0}, {1, 1, 1}};
  const ddo::Octree empty(params, nodes, {});
  ASSERT_TRUE(empty.objects().empty());
  ddo::FileExpectation e;
  e.scene_checksum = 42;
  e.triangles = 0;
  e.objects = 0;
  TempPath file("no_objects.ddo");
  ddo::saveOctree(empty, e, file.path);
  const ddo::Octree back = ddo::loadOctree(file.path, e);
  EXPECT_EQ(back.nodes().size(), 1u);
  EXPECT_TRUE(back.objects().empty());
  EXPECT_EQ(back.masks(), empty.masks());
}

TEST(DdoFile, RefusesStaleForeignTruncatedCorruptAndOtherwiseBuiltFiles) {
  const TriangleScene s = scene();
  ddo::BuildArgs args;
  args.leaf_triangles = 8;
  args.threads = 1;
  const ddo::Octree built = ddo::buildOctree(s.mesh(), args);
  TempPath file("refuse.ddo");
  ddo::saveOctree(built, expectationFor(s), file.path);
  const std::string good = readAll(file.path);

  // Stale: one vertex of the scene moved.
  TriangleScene edited = s;
  edited.positions[7] += 0.25f;
  test::expectError([&] { ddo::loadOctree(file.path, expectationFor(edited)); },
                    ErrorCode::BadInput, {"is stale", "another scene", "rebuild"});
  // Built with other parameters than asked for.
  ddo::FileExpectation other = expectationFor(s);
  other.regions = 32;
  test::expectError([&] { ddo::loadOctree(file.path, other); }, ErrorCode::BadInput,
                    {"64 regions", "32"});
  // Foreign: not a DDO file at all.
  writeAll(file.path, "ply\nformat ascii 1.0\n");
  test::expectError([&] { ddo::loadOctree(file.path, expectationFor(s)); }, ErrorCode::BadInput,
                    {"is not a DDO file"});
  writeAll(file.path, "");
  test::expectError([&] { ddo::loadOctree(file.path, expectationFor(s)); }, ErrorCode::BadInput,
                    {"is not a DDO file"});
  // Truncated and corrupt.
  writeAll(file.path, good.substr(0, good.size() / 2));
  test::expectError([&] { ddo::loadOctree(file.path, expectationFor(s)); }, ErrorCode::BadInput,
                    {"corrupt"});
  std::string flipped = good;
  flipped[flipped.size() / 2] = char(flipped[flipped.size() / 2] ^ 0x10);
  writeAll(file.path, flipped);
  test::expectError([&] { ddo::loadOctree(file.path, expectationFor(s)); }, ErrorCode::BadInput,
                    {"corrupt"});
  // Another format version.
  std::string version = good;
  version[8] = 9;
  writeAll(file.path, version);
  test::expectError([&] { ddo::loadOctree(file.path, expectationFor(s)); }, ErrorCode::BadInput,
                    {"format version 9"});
  // Missing file, unwritable folder.
  test::expectError([&] { ddo::loadOctree(file.path + ".absent", expectationFor(s)); },
                    ErrorCode::Environment, {"cannot read"});
  test::expectError([&] { ddo::saveOctree(built, expectationFor(s), "/nonexistent-folder/x.ddo"); },
                    ErrorCode::Environment, {"cannot write"});
  // And the good bytes still load.
  writeAll(file.path, good);
  EXPECT_EQ(ddo::loadOctree(file.path, expectationFor(s)).masks(), built.masks());
}

// The result forms (logrid/error.hpp): tryLoadOctree() and trySaveOctree() return the
// error loadOctree() and saveOctree() throw, with the same code and message, also where
// the reader stops inside the file (a field cut off, an inconsistent node): files whose
// checksum was recomputed after the damage, as the fuzzer makes them.
TEST(DdoFile, TryLoadAndTrySaveReturnWhatLoadAndSaveThrow) {
  const TriangleScene s = scene();
  ddo::BuildArgs args;
  args.leaf_triangles = 8;
  args.threads = 1;
  const ddo::Octree built = ddo::buildOctree(s.mesh(), args);
  const ddo::FileExpectation expect = expectationFor(s);
  TempPath file("try.ddo");
  ASSERT_TRUE(ddo::trySaveOctree(built, expect, file.path).ok());
  const std::string good = readAll(file.path);
  auto refused = [&](const std::string& bytes, ErrorCode code,
                     std::initializer_list<std::string> parts) {
    writeAll(file.path, bytes);
    test::expectBothForms([&] { return ddo::tryLoadOctree(file.path, expect); },
                          [&] { ddo::loadOctree(file.path, expect); }, code, parts);
  };
  // The trailing checksum recomputed over what precedes it.
  auto resealed = [](std::string bytes) {
    const std::uint64_t sum = ddo::payloadChecksum(
        reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size() - 8);
    std::memcpy(&bytes[bytes.size() - 8], &sum, 8);
    return bytes;
  };
  // The magic, then half of the format version.
  refused(good.substr(0, 10), ErrorCode::BadInput, {file.path, "is truncated", "rebuild"});
  refused(resealed(good.substr(0, good.size() - 20)), ErrorCode::BadInput,
          {file.path, "is truncated or has inconsistent sizes"});
  // Node 0 (after the 8-byte magic, the version, the scene's 24 bytes, the 52 bytes of
  // parameters and the two counts) at level 5: the root must be at level 0.
  std::string level = good;
  level[8 + 4 + 24 + 52 + 16 + 52] = 5;
  refused(resealed(level), ErrorCode::BadInput, {"describes an inconsistent octree (node 0)"});
  refused("ply\n", ErrorCode::BadInput, {"is not a DDO file"});
  test::expectBothForms([&] { return ddo::tryLoadOctree(file.path + ".absent", expect); },
                        [&] { ddo::loadOctree(file.path + ".absent", expect); },
                        ErrorCode::Environment, {"cannot read the DDO file"});
  test::expectBothForms(
      [&] { return ddo::trySaveOctree(built, expect, "/nonexistent-folder/x.ddo"); },
      [&] { ddo::saveOctree(built, expect, "/nonexistent-folder/x.ddo"); }, ErrorCode::Environment,
      {"cannot write the DDO file", "/nonexistent-folder/x.ddo.partial"});
  writeAll(file.path, good);
  const Result<ddo::Octree> loaded = ddo::tryLoadOctree(file.path, expect);
  ASSERT_TRUE(loaded.ok()) << loaded.status().message();
  EXPECT_EQ(loaded->masks(), built.masks());
  EXPECT_EQ(loaded->objects(), built.objects());
}

}  // namespace
}  // namespace logrid
