// A short, deterministic smoke fuzzer for loadSceneFile: valid files of each format
// (those of tests/unit/loader_test.cpp, regenerated here) are mutated with a fixed seed
// -- bit flips, truncations, huge numbers, duplicated and deleted chunks -- and each
// result must either load into a Scene that passes validateScene or throw logrid::Error.
// Any other exception fails the test; a crash inside assimp takes the process down, a
// hang makes the watchdog abort it, and either way the input that did it is left on disk
// (its path is printed first). Longer runs of the same mutations (tens of thousands of
// inputs a format, each load in a child process) found the assimp 5.2 bugs that
// loader.cpp works around; this test keeps the run short and checks they stay fixed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "logrid/error.hpp"
#include "scene/loader.hpp"
#include "scene/scene.hpp"

// Assimp 5.2 leaks memory on the error paths of some importers (OBJ, ASCII STL, PLY,
// glTF) when a file is malformed. In sanitizer builds LeakSanitizer would fail this test
// for it; its leaks, and only those whose stack runs through assimp, are suppressed.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so"; }

namespace logrid::samples {
namespace {

// --- The valid files (as in loader_test.cpp) -----------------------------------------

const char* const kObjTwoObjects =
    "# two objects\n"
    "o first\n"
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
    "f 1 2 3\nf 2 4 3\n"
    "o second\n"
    "v 0 0 5\nv 2 0 5\nv 0 3 5\n"
    "f 5 6 7\n";

const char* const kPlyAscii =
    "ply\n"
    "format ascii 1.0\n"
    "comment logrid test\n"
    "element vertex 5\n"
    "property float x\nproperty float y\nproperty float z\n"
    "element face 2\n"
    "property list uchar int vertex_indices\n"
    "end_header\n"
    "-1 0 0\n1 0 0\n1 2 0\n-1 2 0\n0 1 4\n"
    "4 0 1 2 3\n"
    "3 0 1 4\n";

const char* const kStlAscii =
    "solid square\n"
    " facet normal 0 1 0\n  outer loop\n"
    "   vertex 0 0 0\n   vertex 0 0 3\n   vertex 3 0 0\n"
    "  endloop\n endfacet\n"
    " facet normal 0 1 0\n  outer loop\n"
    "   vertex 3 0 0\n   vertex 0 0 3\n   vertex 3 0 3\n"
    "  endloop\n endfacet\n"
    "endsolid square\n";

template <typename T>
void appendRaw(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // the tests run on little-endian machines
  out.append(bytes, sizeof(T));
}

std::string binaryPlyTetrahedron() {
  std::string out =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
      "property float y\nproperty float z\nelement face 4\n"
      "property list uchar int vertex_indices\nend_header\n";
  for (const float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 2.f, 0.f, 0.f, 0.f, 3.f}) {
    appendRaw(out, v);
  }
  const std::int32_t faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& face : faces) {
    out.push_back(3);
    for (const std::int32_t index : face) appendRaw(out, index);
  }
  return out;
}

std::string base64(const std::string& bytes) {
  static const char* const kDigits =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::uint32_t bits = 0;
  int count = 0;
  for (const char c : bytes) {
    bits = bits << 8 | static_cast<unsigned char>(c);
    count += 8;
    while (count >= 6) {
      count -= 6;
      out.push_back(kDigits[(bits >> count) & 63u]);
    }
  }
  if (count > 0) out.push_back(kDigits[(bits << (6 - count)) & 63u]);
  while (out.size() % 4 != 0) out.push_back('=');
  return out;
}

std::string gltfBuffer() {
  std::string buffer;
  for (const float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) appendRaw(buffer, v);
  for (const int i : {0, 1, 2}) appendRaw(buffer, static_cast<std::uint16_t>(i));
  buffer.append(2, '\0');
  return buffer;
}

std::string gltfInstanced(const std::string& buffer_uri) {
  return R"({
  "asset": {"version": "2.0", "generator": "logrid loader_fuzz_test"},
  "scene": 0,
  "scenes": [{"nodes": [0]}],
  "nodes": [
    {"name": "root", "scale": [2, 2, 2], "children": [1, 2]},
    {"name": "east", "mesh": 0, "translation": [10, 0, 0]},
    {"name": "south", "mesh": 0, "translation": [0, 0, -10]}
  ],
  "meshes": [{"name": "triangle", "primitives": [
    {"attributes": {"POSITION": 0}, "indices": 1, "material": 0, "mode": 4}]}],
  "materials": [{"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}}],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
     "min": [0, 0, 0], "max": [1, 1, 0]},
    {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}
  ],
  "bufferViews": [
    {"buffer": 0, "byteOffset": 0, "byteLength": 36, "target": 34962},
    {"buffer": 0, "byteOffset": 36, "byteLength": 6, "target": 34963}
  ],
  "buffers": [{"byteLength": 44)" +
         (buffer_uri.empty() ? std::string() : ", \"uri\": \"" + buffer_uri + "\"") + R"(}]
})";
}

std::string gltfEmbedded() {
  return gltfInstanced("data:application/octet-stream;base64," + base64(gltfBuffer()));
}

std::string glbInstanced() {
  std::string json = gltfInstanced("");
  json.append((4 - json.size() % 4) % 4, ' ');
  const std::string bin = gltfBuffer();
  std::string out = "glTF";
  auto word = [&out](std::size_t value) { appendRaw(out, static_cast<std::uint32_t>(value)); };
  word(2);
  word(12 + 8 + json.size() + 8 + bin.size());
  word(json.size());
  out += "JSON" + json;
  word(bin.size());
  out += std::string("BIN\0", 4) + bin;
  return out;
}

// The two facets of kStlAscii as binary STL: 80-byte header, count, 50 bytes a facet.
std::string binaryStl() {
  std::string out(80, ' ');
  out.replace(0, 11, "logrid test");
  appendRaw(out, std::uint32_t{2});
  const float facets[2][12] = {{0, 1, 0, 0, 0, 0, 0, 0, 3, 3, 0, 0},
                               {0, 1, 0, 3, 0, 0, 0, 0, 3, 3, 0, 3}};
  for (const auto& facet : facets) {
    for (const float v : facet) appendRaw(out, v);
    appendRaw(out, std::uint16_t{0});
  }
  return out;
}

struct SeedFile {
  const char* name;       // for test names
  const char* extension;  // with the dot
  std::string (*make)();
};

const SeedFile kSeeds[] = {
    {"Obj", ".obj", [] { return std::string(kObjTwoObjects); }},
    {"AsciiPly", ".ply", [] { return std::string(kPlyAscii); }},
    {"BinaryPly", ".ply", binaryPlyTetrahedron},
    {"AsciiStl", ".stl", [] { return std::string(kStlAscii); }},
    {"BinaryStl", ".stl", binaryStl},
    {"Gltf", ".gltf", gltfEmbedded},
    {"Glb", ".glb", glbInstanced},
};

// --- Mutations -----------------------------------------------------------------------

// splitmix64: the same sequence with every standard library (std:: distributions are
// not specified bit for bit).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform enough in [0, n) for n > 0.
  std::size_t below(std::size_t n) { return static_cast<std::size_t>(next() % n); }

 private:
  std::uint64_t state_;
};

// Numbers that overflow counts, sizes and indices in text formats.
const char* const kHugeText[] = {
    "4294967295",           "4294967296", "2147483647", "-2147483648", "-1",  "65535", "65536",
    "18446744073709551615", "1e38",       "-1e39",      "1e999",       "nan", "inf",   "0",
    "999999999999999999999"};
// The same in binary, for counts and indices of binary formats.
const std::uint32_t kHugeBinary[] = {0xFFFFFFFFu,         0x7FFFFFFFu,         0x80000000u,
                                     0x7FC00000u /*NaN*/, 0x7F800000u /*inf*/, 0x0000FFFFu,
                                     0x00010000u};

// Input files are capped so that duplicated chunks cannot grow without bound.
constexpr std::size_t kMaxInputBytes = 1 << 16;

void mutateOnce(std::string& s, Rng& rng) {
  const std::size_t size = s.size();
  const std::size_t at = size == 0 ? 0 : rng.below(size);
  switch (rng.below(8)) {
    case 0:  // flip a bit
      if (size > 0) s[at] = static_cast<char>(s[at] ^ (1 << rng.below(8)));
      break;
    case 1:  // a random byte
      if (size > 0) s[at] = static_cast<char>(rng.below(256));
      break;
    case 2:  // truncate
      s.resize(at);
      break;
    case 3:  // insert a huge number as text
      s.insert(at, kHugeText[rng.below(std::size(kHugeText))]);
      break;
    case 4: {  // replace the next number with a huge one
      std::size_t begin = s.find_first_of("0123456789", at);
      if (begin == std::string::npos) break;
      if (begin > 0 && s[begin - 1] == '-') --begin;
      const std::size_t end = s.find_first_not_of("0123456789.eE+-", begin + 1);
      s.replace(begin, (end == std::string::npos ? s.size() : end) - begin,
                kHugeText[rng.below(std::size(kHugeText))]);
      break;
    }
    case 5: {  // overwrite four bytes with a huge binary value
      if (size < 4) break;
      const std::uint32_t value = kHugeBinary[rng.below(std::size(kHugeBinary))];
      std::memcpy(&s[std::min(at, size - 4)], &value, 4);
      break;
    }
    case 6: {  // duplicate a chunk somewhere
      if (size == 0) break;
      const std::size_t length = 1 + rng.below(std::min<std::size_t>(size - at, 256));
      const std::string chunk = s.substr(at, length);
      s.insert(rng.below(size + 1), chunk);
      break;
    }
    default: {  // delete a chunk
      if (size == 0) break;
      s.erase(at, 1 + rng.below(std::min<std::size_t>(size - at, 64)));
      break;
    }
  }
  if (s.size() > kMaxInputBytes) s.resize(kMaxInputBytes);
}

// --- A watchdog for hangs ------------------------------------------------------------

// Aborts the process, naming the input, when one load takes longer than the limit: a
// hang inside assimp then fails loudly with a reproducer instead of running into the
// test runner's timeout.
class Watchdog {
 public:
  explicit Watchdog(std::chrono::seconds limit) : limit_(limit), thread_([this] { run(); }) {}
  ~Watchdog() {
    stop_ = true;
    thread_.join();
  }
  void arm(const std::string* what) {
    what_ = what;
    since_ = now();
  }
  void disarm() { since_ = -1; }

 private:
  static std::int64_t now() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
  void run() {
    while (!stop_) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      const std::int64_t since = since_;
      if (since >= 0 && now() - since > std::chrono::milliseconds(limit_).count()) {
        std::fprintf(stderr, "loader_fuzz_test: one load took over %llds, giving up: %s\n",
                     static_cast<long long>(limit_.count()), what_.load()->c_str());
        std::abort();
      }
    }
  }

  std::chrono::seconds limit_;
  std::atomic<bool> stop_{false};
  std::atomic<std::int64_t> since_{-1};
  std::atomic<const std::string*> what_{nullptr};
  std::thread thread_;
};

// --- The test ------------------------------------------------------------------------

constexpr int kInputsPerFormat = 1500;

// Mutates the seed file kInputsPerFormat times and loads each result.
void fuzz(const char* name) {
  const SeedFile& seed = *std::find_if(
      std::begin(kSeeds), std::end(kSeeds),
      [name](const SeedFile& candidate) { return std::strcmp(candidate.name, name) == 0; });
  const std::string valid = seed.make();
  const std::string path = testing::TempDir() + "logrid_loader_fuzz_" + std::to_string(::getpid()) +
                           "_" + seed.name + seed.extension;
  // Printed first: after a crash this file holds the input that caused it.
  std::printf("inputs are written to %s\n", path.c_str());
  std::fflush(stdout);

  // The unmutated file must load, or the mutations test nothing.
  std::ofstream(path, std::ios::binary).write(valid.data(), std::streamsize(valid.size()));
  ASSERT_NO_THROW(validateScene(loadSceneFile(path)));

  std::uint64_t name_hash = 0xCBF29CE484222325ull;  // FNV-1a: the same everywhere
  for (const char* c = seed.name; *c != '\0'; ++c) {
    name_hash = (name_hash ^ static_cast<unsigned char>(*c)) * 0x100000001B3ull;
  }
  Rng rng(0x6C6F67726964ull ^ name_hash);
  Watchdog watchdog(std::chrono::seconds(20));
  int loaded = 0, refused = 0;
  for (int i = 0; i < kInputsPerFormat; ++i) {
    std::string input = valid;
    const std::size_t mutations = 1 + rng.below(4);
    for (std::size_t m = 0; m < mutations; ++m) mutateOnce(input, rng);
    {
      std::ofstream out(path, std::ios::binary);
      out.write(input.data(), std::streamsize(input.size()));
    }
    const std::string what = path + " (input " + std::to_string(i) + ")";
    watchdog.arm(&what);
    try {
      const Scene scene = loadSceneFile(path);
      watchdog.disarm();
      EXPECT_NO_THROW(validateScene(scene)) << what;
      EXPECT_FALSE(scene.objects.empty()) << what;
      ++loaded;
    } catch (const Error& e) {
      watchdog.disarm();
      // The message names the file.
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      ++refused;
    } catch (const std::exception& e) {
      watchdog.disarm();
      const std::string keep = path + ".failure" + std::to_string(i) + seed.extension;
      std::filesystem::copy_file(path, keep, std::filesystem::copy_options::overwrite_existing);
      ADD_FAILURE() << what << ": not a logrid::Error: " << e.what() << " (input kept as " << keep
                    << ")";
    } catch (...) {
      watchdog.disarm();
      ADD_FAILURE() << what << ": an exception that is not a std::exception";
    }
  }
  std::error_code ec;
  std::filesystem::remove(path, ec);
  std::printf("%s: %d mutated inputs loaded, %d refused with logrid::Error\n", seed.name, loaded,
              refused);
  // Both outcomes should occur, or the mutations are too weak or too strong to mean much.
  EXPECT_GT(loaded, 0);
  EXPECT_GT(refused, 0);
}

TEST(LoaderFuzz, Obj) { fuzz("Obj"); }
TEST(LoaderFuzz, AsciiPly) { fuzz("AsciiPly"); }
TEST(LoaderFuzz, BinaryPly) { fuzz("BinaryPly"); }
TEST(LoaderFuzz, AsciiStl) { fuzz("AsciiStl"); }
TEST(LoaderFuzz, BinaryStl) { fuzz("BinaryStl"); }
TEST(LoaderFuzz, Gltf) { fuzz("Gltf"); }
TEST(LoaderFuzz, Glb) { fuzz("Glb"); }

}  // namespace
}  // namespace logrid::samples
