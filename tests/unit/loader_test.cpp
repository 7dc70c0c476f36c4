// Tests of loadSceneFile: small files of each common format, written by the test, load
// with the right triangles, objects and bounds; broken files give a logrid::Error with
// the expected code and a message that names the file and the problem.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "logrid/error.hpp"
#include "model_files.hpp"
#include "scene/loader.hpp"
#include "scene/scene.hpp"

namespace logrid::samples {
namespace {

namespace fs = std::filesystem;

// --- Files of each format (tests/support/model_files.hpp) ----------------------------

using test::binaryPly;
using test::binaryPlyTetrahedron;
using test::binaryStl;
using test::kObjTwoObjects;
using test::kPlyAscii;
using test::kStlAscii;

// The glTF files with this test's asset.generator.
std::string gltfEmbedded() { return test::gltfEmbedded("logrid loader_test"); }
std::string glbInstanced() { return test::glbInstanced("logrid loader_test"); }

// The glTF file with its node array replaced.
std::string gltfWithNodes(const std::string& nodes) {
  std::string gltf = gltfEmbedded();
  const std::size_t begin = gltf.find("\n  \"nodes\": [") + 3;
  const std::size_t end = gltf.find("\n  ],\n  \"meshes\"") + 4;
  return gltf.replace(begin, end - begin, "\"nodes\": " + nodes);
}

// --- Fixture -------------------------------------------------------------------------

class LoaderTest : public testing::Test {
 protected:
  void TearDown() override {
    std::error_code ec;
    for (const std::string& path : created_) fs::remove_all(path, ec);
  }

  // A path under the test's temporary directory, unique to this process and test.
  std::string tempPath(const std::string& name) {
    const testing::TestInfo* info = testing::UnitTest::GetInstance()->current_test_info();
    std::string path =
        test::tempFilePath("logrid_loader", std::string(info->name()) + "_" +
                                                std::to_string(created_.size()) + "_" + name);
    created_.push_back(path);
    return path;
  }

  std::string writeFile(const std::string& name, const std::string& bytes) {
    const std::string path = tempPath(name);
    test::writeBytes(path, bytes);
    return path;
  }

  // Loads `path`, collecting the loader's warnings instead of printing them.
  static Scene loadCollecting(const std::string& path, std::vector<std::string>& warnings) {
    LoadOptions options;
    options.warn = [&](const std::string& message) { warnings.push_back(message); };
    return loadSceneFile(path, options);
  }

  // Expects loading `path` to throw logrid::Error with `code`, a message naming the file
  // and containing each of `needles`.
  static void expectError(const std::string& path, ErrorCode code,
                          const std::vector<std::string>& needles,
                          const LoadOptions& options = {}) {
    try {
      const Scene scene = loadSceneFile(path, options);
      ADD_FAILURE() << path << " loaded (" << scene.triangleCount() << " triangles)";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_EQ(toString(e.code()), std::string(toString(code))) << message;
      EXPECT_NE(message.find(path), std::string::npos) << message;
      for (const std::string& needle : needles) {
        EXPECT_NE(message.find(needle), std::string::npos)
            << "'" << needle << "' not in: " << message;
      }
    } catch (const std::exception& e) {
      ADD_FAILURE() << path << ": not a logrid::Error: " << e.what();
    } catch (...) {
      ADD_FAILURE() << path << ": an exception that is not a std::exception";
    }
  }

 private:
  std::vector<std::string> created_;
};

void expectWorldBounds(const Scene& scene, glm::dvec3 lo, glm::dvec3 hi) {
  const double tolerance = 1e-5;
  EXPECT_NEAR(scene.origin.x + scene.bounds.min.x, lo.x, tolerance);
  EXPECT_NEAR(scene.origin.y + scene.bounds.min.y, lo.y, tolerance);
  EXPECT_NEAR(scene.origin.z + scene.bounds.min.z, lo.z, tolerance);
  EXPECT_NEAR(scene.origin.x + scene.bounds.max.x, hi.x, tolerance);
  EXPECT_NEAR(scene.origin.y + scene.bounds.max.y, hi.y, tolerance);
  EXPECT_NEAR(scene.origin.z + scene.bounds.max.z, hi.z, tolerance);
  // The local origin is the centre of the bounds.
  EXPECT_NEAR(scene.origin.x, 0.5 * (lo.x + hi.x), tolerance);
  EXPECT_NEAR(scene.origin.y, 0.5 * (lo.y + hi.y), tolerance);
  EXPECT_NEAR(scene.origin.z, 0.5 * (lo.z + hi.z), tolerance);
}

// The checks every loaded scene must pass besides its counts and bounds.
void expectWellFormed(const Scene& scene) {
  EXPECT_NO_THROW(validateScene(scene));
  EXPECT_FALSE(scene.split_by_triangles);
  for (const SceneObject& object : scene.objects) {
    EXPECT_GT(object.index_count, 0u);
    EXPECT_EQ(object.color >> 24, 0xFFu) << "object colours are opaque";
    EXPECT_LE(object.box.min.x, object.box.max.x);
  }
  EXPECT_GT(scene.near_plane, 0.0);
  EXPECT_GT(scene.far_plane, scene.near_plane);
  // The default orbit: 8+ keys, outside the bounds, looking at the bounds' centre.
  ASSERT_GE(scene.path.keys().size(), 8u);
  const double dx = scene.bounds.max.x - scene.bounds.min.x;
  const double dy = scene.bounds.max.y - scene.bounds.min.y;
  const double dz = scene.bounds.max.z - scene.bounds.min.z;
  const double radius = 0.5 * std::sqrt(dx * dx + dy * dy + dz * dz);
  const glm::dvec3 centre{scene.origin.x + 0.5 * (scene.bounds.min.x + scene.bounds.max.x),
                          scene.origin.y + 0.5 * (scene.bounds.min.y + scene.bounds.max.y),
                          scene.origin.z + 0.5 * (scene.bounds.min.z + scene.bounds.max.z)};
  for (const CameraKey& key : scene.path.keys()) {
    EXPECT_NEAR(key.look_at.x, centre.x, 1e-6);
    EXPECT_NEAR(key.look_at.y, centre.y, 1e-6);
    EXPECT_NEAR(key.look_at.z, centre.z, 1e-6);
    const double ex = key.position.x - centre.x, ey = key.position.y - centre.y,
                 ez = key.position.z - centre.z;
    EXPECT_NEAR(std::sqrt(ex * ex + ey * ey + ez * ez), 1.2 * radius, 1e-6 * radius + 1e-9);
    EXPECT_GT(ey, 0.0) << "the orbit runs above the centre";
  }
  EXPECT_GT(scene.far_plane, 2.2 * radius) << "the far plane covers the model from the orbit";
  EXPECT_LT(scene.far_plane, 10 * radius);
}

// --- Valid files ---------------------------------------------------------------------

TEST(LoaderSupport, AssimpIsAvailableInThisBuild) { EXPECT_TRUE(sceneFilesSupported()); }

TEST_F(LoaderTest, ObjWithTwoObjects) {
  const std::string path = writeFile("two.obj", kObjTwoObjects);
  const Scene scene = loadSceneFile(path);
  EXPECT_EQ(scene.triangleCount(), 3u);
  ASSERT_EQ(scene.objects.size(), 2u);
  EXPECT_EQ(scene.objects[0].index_count, 6u);
  EXPECT_EQ(scene.objects[1].index_count, 3u);
  EXPECT_NE(scene.objects[0].color, scene.objects[1].color) << "default material: palette";
  EXPECT_EQ(scene.name, fs::path(path).stem().string());
  expectWorldBounds(scene, {0, 0, 0}, {2, 3, 5});
  // Object boxes are local too: the triangle sits at z = 5, i.e. 2.5 above the centre.
  EXPECT_NEAR(scene.objects[1].box.min.z, 2.5f, 1e-6);
  EXPECT_NEAR(scene.objects[1].box.max.z, 2.5f, 1e-6);
  expectWellFormed(scene);
}

TEST_F(LoaderTest, ObjMaterialColour) {
  const std::string mtl = writeFile("blue.mtl", "newmtl blue\nKd 0 0 1\n");
  const std::string obj = "mtllib " + fs::path(mtl).filename().string() +
                          "\nusemtl blue\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const Scene scene = loadSceneFile(writeFile("blue.obj", obj));
  ASSERT_EQ(scene.objects.size(), 1u);
  EXPECT_EQ(scene.objects[0].color, 0xFFFF0000u);  // RGBA8 little-endian: opaque blue
}

TEST_F(LoaderTest, AsciiPly) {
  std::vector<std::string> warnings;
  const Scene scene = loadCollecting(writeFile("ascii.ply", kPlyAscii), warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(scene.triangleCount(), 3u);
  EXPECT_EQ(scene.objects.size(), 1u);
  expectWorldBounds(scene, {-1, 0, 0}, {1, 2, 4});
  expectWellFormed(scene);
}

TEST_F(LoaderTest, BinaryPly) {
  std::vector<std::string> warnings;
  const Scene scene = loadCollecting(writeFile("binary.ply", binaryPlyTetrahedron()), warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(scene.triangleCount(), 4u);
  EXPECT_EQ(scene.objects.size(), 1u);
  EXPECT_EQ(scene.positions.size(), 4u * 3) << "identical vertices are shared";
  expectWorldBounds(scene, {0, 0, 0}, {1, 2, 3});
  expectWellFormed(scene);
}

// Files as real exporters wrote them (tests/support/model_files.hpp): assimp reads them
// correctly, so they load, with a warning where they bend the format.
TEST_F(LoaderTest, PlyFromRealExporters) {
  const struct {
    const char* name;
    const char* bytes;
    std::vector<std::string> warnings;  // a phrase of each expected warning, in order
  } kFiles[] = {
      {"blender245.ply",
       test::kPlyBlender245,
       {"a header line that is no PLY keyword (assimp ignores it) (header line 3, 'Created by "
        "Blender3D 245 - www.blender.org, source file: untitled.blend')"}},
      {"blender249.ply", test::kPlyBlender249, {}},
      {"decimal_comma.ply",
       test::kPlyDecimalCommaCrLf,
       {"numbers with a decimal comma (assimp reads them as with a point) (15 times, first "
        "data line 1 ('vertex'), '-1,000000')",
        "data after the last element (assimp ignores it) (data line 8)"}},
  };
  for (const auto& file : kFiles) {
    SCOPED_TRACE(file.name);
    const std::string path = writeFile(file.name, file.bytes);
    std::vector<std::string> warnings;
    const Scene scene = loadCollecting(path, warnings);
    EXPECT_EQ(scene.triangleCount(), 3u);
    EXPECT_EQ(scene.objects.size(), 1u);
    expectWorldBounds(scene, {-1, 0, 0}, {1, 2, 4});
    expectWellFormed(scene);
    std::string all;
    for (const std::string& w : warnings) {
      EXPECT_EQ(w.rfind(path + ": ", 0), 0u) << "the warning names the file: " << w;
      all += w + "\n";
    }
    std::size_t at = 0;
    for (const std::string& phrase : file.warnings) {
      const std::size_t found = all.find(phrase, at);
      EXPECT_NE(found, std::string::npos) << "'" << phrase << "' not (in order) in:\n" << all;
      if (found != std::string::npos) at = found;
    }
    if (file.warnings.empty()) {
      EXPECT_EQ(all, "");
    }
  }
}

// Each of these bends the PLY format in a way assimp 5.2 reads correctly (found by
// experiment): the file loads, with one warning saying what assimp does with it.
TEST_F(LoaderTest, PlyThatBendsItsFormatLoadsWithAWarning) {
  auto replaced = [](std::string text, const std::string& from, const std::string& to) {
    return text.replace(text.find(from), from.size(), to);
  };
  const std::string ply = kPlyAscii;
  const struct {
    const char* name;
    std::string bytes;
    const char* warning;
  } kCases[] = {
      {"free_text.ply", replaced(ply, "element face", "exported by hand\nelement face"),
       "header line 8, 'exported by hand'"},
      {"blank_header.ply", replaced(ply, "element face", "  \nelement face"),
       "a header line of blanks (assimp ignores it) (header line 8)"},
      {"second_format.ply", replaced(ply, "end_header", "format ascii 1.0\nend_header"),
       "header line 10, 'format ascii 1.0'"},
      {"count_junk.ply", replaced(ply, "vertex 5", "vertex 5x"),
       "count followed by other characters (assimp reads the digits) (header line 4, '5x')"},
      {"count_words.ply", replaced(ply, "vertex 5", "vertex 5 points"),
       "extra words after an element count"},
      {"early_property.ply", replaced(ply, "element vertex", "property float w\nelement vertex"),
       "a property before the first element (assimp ignores it) (header line 4)"},
      {"name_words.ply", replaced(ply, "float z", "float z coordinate"),
       "extra words after a property name"},
      {"end_words.ply", replaced(ply, "end_header", "end_header now"),
       "extra words after end_header"},
      {"unknown_last.ply",
       replaced(replaced(replaced(ply, "float z", "float z\nproperty int64 id"), "-1 0 0\n",
                         "-1 0 0 7\n"),
                "0 1 4\n", "0 1 4 8\n"),
       "type assimp does not know (ignored, with its values) (header line 8, 'property int64 id')"},
      {"extra_values.ply", replaced(ply, "3 0 1 4\n", "3 0 1 4 0.5 0.5\n"),
       "more values than their element declares (assimp ignores the rest of the line) (data "
       "line 7 ('face'))"},
      {"empty_line.ply", replaced(ply, "4 0 1 2 3\n", "\n4 0 1 2 3\n"),
       "empty data lines (assimp skips them) (data line 6)"},
      {"trailing.ply", ply + "1 2 3\n", "data after the last element (assimp ignores it)"},
      {"binary_trailing.bin.ply", test::binaryPlyTetrahedron() + "extra",
       "bytes after the last element (assimp ignores them) (5 bytes)"},
  };
  for (const auto& c : kCases) {
    SCOPED_TRACE(c.name);
    std::vector<std::string> warnings;
    const Scene scene = loadCollecting(writeFile(c.name, c.bytes), warnings);
    const bool tetrahedron = std::string(c.name).find(".bin.") != std::string::npos;
    EXPECT_EQ(scene.triangleCount(), tetrahedron ? 4u : 3u);
    if (tetrahedron) {
      expectWorldBounds(scene, {0, 0, 0}, {1, 2, 3});
    } else {
      expectWorldBounds(scene, {-1, 0, 0}, {1, 2, 4});
    }
    ASSERT_EQ(warnings.size(), 1u) << (warnings.empty() ? "no warning" : warnings[0]);
    EXPECT_NE(warnings[0].find(c.warning), std::string::npos) << warnings[0];
  }
}

TEST_F(LoaderTest, AsciiStl) {
  const Scene scene = loadSceneFile(writeFile("square.stl", kStlAscii));
  EXPECT_EQ(scene.triangleCount(), 2u);
  EXPECT_EQ(scene.objects.size(), 1u);
  expectWorldBounds(scene, {0, 0, 0}, {3, 0, 3});
  expectWellFormed(scene);
}

TEST_F(LoaderTest, BinaryStl) {
  const Scene scene = loadSceneFile(writeFile("square_binary.stl", binaryStl()));
  EXPECT_EQ(scene.triangleCount(), 2u);
  EXPECT_EQ(scene.objects.size(), 1u);
  expectWorldBounds(scene, {0, 0, 0}, {3, 0, 3});
  expectWellFormed(scene);
}

TEST_F(LoaderTest, GltfWithEmbeddedBufferInstancesAndTransforms) {
  const Scene scene = loadSceneFile(writeFile("instanced.gltf", gltfEmbedded()));
  EXPECT_EQ(scene.triangleCount(), 2u);
  ASSERT_EQ(scene.objects.size(), 2u) << "one object per (node, mesh) instance";
  expectWorldBounds(scene, {0, 0, -20}, {22, 2, 0});
  // The material's base colour (assimp's diffuse colour), opaque red.
  EXPECT_EQ(scene.objects[0].color, 0xFF0000FFu);
  EXPECT_EQ(scene.objects[1].color, 0xFF0000FFu);
  expectWellFormed(scene);
}

TEST_F(LoaderTest, BinaryGltf) {
  const Scene scene = loadSceneFile(writeFile("instanced.glb", glbInstanced()));
  EXPECT_EQ(scene.triangleCount(), 2u);
  EXPECT_EQ(scene.objects.size(), 2u);
  expectWorldBounds(scene, {0, 0, -20}, {22, 2, 0});
  expectWellFormed(scene);
}

TEST_F(LoaderTest, UppercaseExtensionAndFarFromOrigin) {
  // A model a million units out keeps small local coordinates.
  const std::string obj = "v 1000000 0 0\nv 1000001 0 0\nv 1000000 1 0\nf 1 2 3\n";
  const Scene scene = loadSceneFile(writeFile("far.OBJ", obj));
  EXPECT_EQ(scene.triangleCount(), 1u);
  expectWorldBounds(scene, {1e6, 0, 0}, {1e6 + 1, 1, 0});
  EXPECT_NEAR(scene.bounds.max.x, 0.5f, 1e-6);
  expectWellFormed(scene);
}

TEST_F(LoaderTest, PointsAndLinesAreDropped) {
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 9 9 9\np 4\nl 1 4\nf 1 2 3\n";
  const Scene scene = loadSceneFile(writeFile("mixed.obj", obj));
  EXPECT_EQ(scene.triangleCount(), 1u);
  expectWorldBounds(scene, {0, 0, 0}, {1, 1, 0});
}

TEST_F(LoaderTest, DegenerateModelStillGetsAPath) {
  const Scene scene = loadSceneFile(writeFile("point.obj", "v 1 2 3\nv 1 2 3\nv 1 2 3\nf 1 2 3\n"));
  EXPECT_EQ(scene.triangleCount(), 1u);
  EXPECT_GT(scene.near_plane, 0.0);
  EXPECT_FALSE(scene.path.empty());
}

// --- Broken files --------------------------------------------------------------------

TEST_F(LoaderTest, TruncatedBinaryPly) {
  const std::string full = binaryPlyTetrahedron();
  const std::size_t header = full.find("end_header\n") + 11;
  // Cut inside the vertex data, inside the face data, and between two faces. (Assimp
  // itself would read the missing bytes as 0x0A and fail, if at all, on the indices.)
  expectError(writeFile("cut_vertices.ply", full.substr(0, header + 20)), ErrorCode::BadInput,
              {"truncated"});
  expectError(writeFile("cut_faces.ply", full.substr(0, full.size() - 7)), ErrorCode::BadInput,
              {"'face' 3 of 4", "truncated"});
  expectError(writeFile("cut_face.ply", full.substr(0, full.size() - 13)), ErrorCode::BadInput,
              {"'face' 3 of 4", "truncated"});
}

TEST_F(LoaderTest, TruncatedAsciiPly) {
  // Cut in the header: assimp 5.2 would loop for ever looking for end_header.
  std::string ply = kPlyAscii;
  ply.resize(ply.find("comment") + 10);
  expectError(writeFile("cut_header.ply", ply), ErrorCode::BadInput, {"no end_header"});
  // Cut in the data: assimp would repeat the last line it read for the missing ones.
  ply = kPlyAscii;
  ply.resize(ply.find("4 0 1 2 3"));
  expectError(writeFile("cut_faces.ply", ply), ErrorCode::BadInput,
              {"ends after 0 of 2 'face' lines", "truncated"});
  ply = kPlyAscii;
  ply.resize(ply.find("1 2 0\n") + 3);
  expectError(writeFile("cut_vertices.ply", ply), ErrorCode::BadInput,
              {"data line 3 ('vertex'): too few values"});
}

// Each of these made assimp 5.2 hang, abort or corrupt the heap (see loader_ply.cpp); the
// loader refuses them before assimp sees them.
TEST_F(LoaderTest, PlyThatBreaksAssimp) {
  auto replaced = [](std::string text, const std::string& from, const std::string& to) {
    return text.replace(text.find(from), from.size(), to);
  };
  // Counts far above what the file holds: assimp would loop or allocate that often.
  expectError(writeFile("huge_count.ply", replaced(kPlyAscii, "face 2", "face 4294967295")),
              ErrorCode::BadInput, {"declares 4294967300 element instances", "truncated"});
  expectError(
      writeFile("huge_count64.ply", replaced(kPlyAscii, "face 2", "face 18446744073709551615")),
      ErrorCode::BadInput, {"not a 32-bit count"});
  expectError(writeFile("huge_list.ply", replaced(kPlyAscii, "3 0 1 4", "2147483647 0 1 4")),
              ErrorCode::BadInput, {"'2147483647' is not a count for list 'vertex_indices'"});
  expectError(writeFile("long_list.ply", replaced(kPlyAscii, "3 0 1 4", "200 0 1 4")),
              ErrorCode::BadInput, {"declares 200 values but the line has 3"});
  std::string binary = binaryPly({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2});
  binary = replaced(binary, "list uchar int", "list int int");
  binary.insert(binary.size() - 12, 3, '\xFF');  // the count: 0xFFFFFFFF, negative
  expectError(writeFile("huge_list_binary.ply", binary), ErrorCode::BadInput,
              {"negative list count"});
  // Control bytes in the header (assimp's line reader runs off its buffer).
  expectError(writeFile("nul.ply",
                        replaced(kPlyAscii, "end_header", std::string("\0\x01", 2) + "end_header")),
              ErrorCode::BadInput, {"header line 10 holds the control byte 0x00"});
  // An element declared twice (assimp issue 5729: heap corruption).
  expectError(writeFile("twice.ply",
                        replaced(kPlyAscii, "element face 2", "element vertex 1\nelement face 2")),
              ErrorCode::BadInput, {"element 'vertex' declared twice"});
  // Binary data whose first byte is 0x0A (assimp reads it one byte off).
  const std::uint32_t bits = 0x3F80000Au;  // 1.0000012f, stored 0A 00 80 3F
  float x = 0;
  std::memcpy(&x, &bits, 4);
  expectError(writeFile("lf.ply", binaryPly({x, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2})),
              ErrorCode::BadInput, {"0x0A"});
}

// Each of these makes assimp 5.2 import wrong geometry without a word (found by
// experiment: the comment of each case says what it read); the loader refuses them.
TEST_F(LoaderTest, PlyThatAssimpWouldMisread) {
  auto replaced = [](std::string text, const std::string& from, const std::string& to) {
    return text.replace(text.find(from), from.size(), to);
  };
  const std::string ply = kPlyAscii;
  // Lines among an element's properties end its property list: y and z are dropped, the
  // vertices read as (x, 0, 0) and the faces from the vertex lines.
  expectError(
      writeFile("comment.ply", replaced(ply, "property float y", "comment here\nproperty float y")),
      ErrorCode::BadInput,
      {"header line 7: property 'y' of element 'vertex' comes after header line 6 (a "
       "comment)"});
  expectError(writeFile("free_text.ply",
                        replaced(ply, "property float y", "Created by hand\nproperty float y")),
              ErrorCode::BadInput, {"after header line 6 ('Created by hand')"});
  expectError(writeFile("blanks.ply", replaced(ply, "property float y", " \t\nproperty float y")),
              ErrorCode::BadInput, {"after header line 6 (a line of blanks)"});
  expectError(writeFile("type.ply", replaced(ply, "float y", "flaot y")), ErrorCode::BadInput,
              {"property 'z' of element 'vertex' comes after one of a type assimp does not know"});
  // A form feed ends a header line for assimp (here: z dropped, the last vertex read as
  // (0, 1, 0)).
  expectError(writeFile("form_feed.ply", replaced(ply, "float y", "float y\fy")),
              ErrorCode::BadInput, {"header line 6 holds the control byte 0x0C"});
  // The second declaration's values win.
  expectError(writeFile("twice.ply",
                        replaced(ply, "property float z", "property float z\nproperty float x")),
              ErrorCode::BadInput, {"property 'x' of element 'vertex' declared twice"});
  // Missing values read as 0: the last vertex as (0, 1, 0).
  expectError(writeFile("few.ply", replaced(ply, "0 1 4\n", "0 1\n")), ErrorCode::BadInput,
              {"data line 5 ('vertex'): too few values"});
  // Numbers read in part: "2.0.5 0" as 2.0 and 0.5, a list count "4.0" as 4 and then 0.
  expectError(writeFile("dots.ply", replaced(ply, "\n1 2 0\n", "\n1 2.0.5 0\n")),
              ErrorCode::BadInput, {"'2.0.5' is not a number as a whole"});
  expectError(writeFile("float_count.ply", replaced(ply, "4 0 1 2 3", "4.0 0 1 2 3")),
              ErrorCode::BadInput, {"'4.0' is not a count for list 'vertex_indices'"});
  // A line of blanks (or a CR alone, in a CR LF file) reads as an instance.
  expectError(writeFile("blank_data.ply", replaced(ply, "4 0 1 2 3\n", "  \n4 0 1 2 3\n")),
              ErrorCode::BadInput, {"data line 6 holds only blanks"});
  std::string crlf;
  for (const char c : replaced(ply, "4 0 1 2 3\n", "\n4 0 1 2 3\n")) {
    if (c == '\n') crlf += '\r';
    crlf += c;
  }
  expectError(writeFile("crlf_blank.ply", crlf), ErrorCode::BadInput,
              {"data line 6 holds only blanks"});
  // A NUL before the values: the line is skipped and the next read in its place.
  expectError(
      writeFile("nul_data.ply", replaced(ply, "\n1 0 0\n", std::string("\n\0", 2) + "1 0 0\n")),
      ErrorCode::BadInput, {"data line 2 holds the control byte 0x00"});
}

TEST_F(LoaderTest, NanVertexInObj) {
  const std::string path = writeFile("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  expectError(path, ErrorCode::BadInput, {"vertex", "not finite"});
}

TEST_F(LoaderTest, InfiniteVertexInAsciiPly) {
  std::string ply = kPlyAscii;
  ply.replace(ply.find("0 1 4\n"), 6, "0 1e999\n");  // overflows float: +inf
  ply.insert(ply.find("1e999") + 5, " 4");
  expectError(writeFile("inf.ply", ply), ErrorCode::BadInput, {"not finite"});
}

TEST_F(LoaderTest, IndexOutOfRangeInObj) {
  const std::string path = writeFile("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n");
  expectError(path, ErrorCode::BadInput, {"index out of range"});
}

TEST_F(LoaderTest, IndexOutOfRangeInPly) {
  std::string ply = kPlyAscii;
  ply.replace(ply.find("3 0 1 4\n"), 8, "3 0 1 99\n");
  expectError(writeFile("range_ascii.ply", ply), ErrorCode::BadInput,
              {"face 1 uses vertex 99 but the mesh has 5 vertices"});
  expectError(writeFile("range_binary.ply", binaryPly({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 99})),
              ErrorCode::BadInput, {"face 0 uses vertex 99 but the mesh has 3 vertices"});
}

TEST_F(LoaderTest, EmptyFile) {
  expectError(writeFile("empty.obj", ""), ErrorCode::BadInput, {"empty"});
}

TEST_F(LoaderTest, NoFaces) {
  expectError(writeFile("vertices.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), ErrorCode::BadInput,
              {"no triangles"});
  expectError(writeFile("lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\n"), ErrorCode::BadInput,
              {"no triangles"});
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n";
  expectError(writeFile("vertices.ply", ply), ErrorCode::BadInput, {"no triangles"});
  expectError(writeFile("empty.stl", "solid x\nendsolid x\n"), ErrorCode::BadInput, {});
}

TEST_F(LoaderTest, GarbageWithKnownExtension) {
  std::string garbage;
  std::uint32_t state = 12345;
  for (int i = 0; i < 4096; ++i) {
    state = state * 1664525u + 1013904223u;
    garbage.push_back(static_cast<char>(state >> 24));
  }
  for (const char* extension : {"ply", "gltf", "glb", "stl", "obj", "fbx", "3ds"}) {
    SCOPED_TRACE(extension);
    expectError(writeFile(std::string("garbage.") + extension, garbage), ErrorCode::BadInput, {});
  }
}

TEST_F(LoaderTest, UnknownExtension) {
  expectError(writeFile("model.logridxyz", kObjTwoObjects), ErrorCode::BadInput,
              {"unknown extension '.logridxyz'", ".obj"});
  expectError(writeFile("no_extension", kObjTwoObjects), ErrorCode::BadInput,
              {"no file extension"});
}

TEST_F(LoaderTest, MissingFile) {
  const std::string path = tempPath("missing.obj");
  expectError(path, ErrorCode::Environment, {"no such file"});
}

TEST_F(LoaderTest, Directory) {
  const std::string path = tempPath("folder.obj");
  fs::create_directory(path);
  expectError(path, ErrorCode::Environment, {"directory"});
}

TEST_F(LoaderTest, FileAboveSizeLimit) {
  LoadOptions options;
  options.max_file_bytes = 16;
  const std::string path = writeFile("big.obj", kObjTwoObjects);
  const std::string size = std::to_string(std::strlen(kObjTwoObjects));
  expectError(path, ErrorCode::BadInput, {size + " bytes", "16 bytes", "max_file_bytes"}, options);
}

TEST_F(LoaderTest, TooManyTriangles) {
  LoadOptions options;
  options.max_triangles = 2;
  expectError(writeFile("many.obj", kObjTwoObjects), ErrorCode::BadInput,
              {"more than 2 triangles", "max_triangles"}, options);
  options.max_triangles = 3;
  EXPECT_EQ(loadSceneFile(writeFile("enough.obj", kObjTwoObjects), options).triangleCount(), 3u);
}

// Each of these crashed assimp 5.2 (stack overflow) or ate all memory.
TEST_F(LoaderTest, GltfThatBreaksAssimp) {
  // A chain of 50000 nested nodes.
  std::string chain = "[";
  for (int n = 0; n < 50000; ++n) chain += "{\"children\": [" + std::to_string(n + 1) + "]},";
  chain += "{\"mesh\": 0}]";
  expectError(writeFile("deep.gltf", gltfWithNodes(chain)), ErrorCode::BadInput,
              {"node graph is deeper than 1000 levels"});
  // 40 nodes, each using the next one twice: 2^40 copies.
  std::string dag = "[";
  for (int n = 0; n < 40; ++n) {
    dag += "{\"children\": [" + std::to_string(n + 1) + ", " + std::to_string(n + 1) + "]},";
  }
  dag += "{\"mesh\": 0}]";
  expectError(writeFile("dag.gltf", gltfWithNodes(dag)), ErrorCode::BadInput,
              {"expands to more than"});
  // JSON nested 200000 deep.
  std::string nested = gltfEmbedded();
  nested.insert(nested.find("\"scene\""),
                "\"extras\": " + std::string(200000, '[') + std::string(200000, ']') + ",");
  expectError(writeFile("nested.gltf", nested), ErrorCode::BadInput, {"nests deeper than"});
  // A cycle.
  expectError(writeFile("cycle.gltf", gltfWithNodes("[{\"children\": [1]}, {\"children\": [0]}]")),
              ErrorCode::BadInput, {"cycle"});
  // A binary glTF whose JSON chunk claims 2 GiB (assimp allocates it before reading).
  std::string glb = glbInstanced();
  glb.replace(12, 4, std::string("\xFF\xFF\xFF\x7F", 4));
  expectError(writeFile("chunk.glb", glb), ErrorCode::BadInput,
              {"a JSON chunk of 2147483647 bytes"});
  glb = glbInstanced();
  expectError(writeFile("cut.glb", glb.substr(0, glb.size() / 2)), ErrorCode::BadInput,
              {"truncated"});
  // A node used twice is fine: two objects.
  const Scene twice = loadSceneFile(
      writeFile("twice.gltf", gltfWithNodes("[{\"children\": [1, 1]}, {\"mesh\": 0}]")));
  EXPECT_EQ(twice.objects.size(), 2u);
}

}  // namespace
}  // namespace logrid::samples
