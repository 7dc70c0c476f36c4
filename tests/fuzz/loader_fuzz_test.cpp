// A short, deterministic smoke fuzzer for loadSceneFile: valid files of each format
// (tests/support/model_files.hpp, shared with loader_test.cpp) are mutated with a fixed seed
// -- bit flips, truncations, huge numbers, duplicated and deleted chunks -- and each
// result must either load into a Scene that passes validateScene or throw logrid::Error.
// Any other exception fails the test; a crash inside assimp takes the process down, a
// hang makes the watchdog abort it, and either way the input that did it is left on disk
// (its path is printed first). Longer runs of the same mutations (tens of thousands of
// inputs a format, each load in a child process) found the assimp 5.2 bugs that
// the loader (loader_ply.cpp, loader_gltf.cpp, loader_assimp_scene.cpp) works around;
// this test keeps the run short and checks they stay fixed.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "logrid/error.hpp"
#include "model_files.hpp"
#include "scene/loader.hpp"
#include "scene/scene.hpp"

// Assimp 5.2 leaks memory on the error paths of some importers (OBJ, ASCII STL, PLY,
// glTF) when a file is malformed. In sanitizer builds LeakSanitizer would fail this test
// for it; its leaks, and only those whose stack runs through assimp, are suppressed.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so"; }

namespace logrid::samples {
namespace {

// --- The valid files (tests/support/model_files.hpp) ---------------------------------

struct SeedFile {
  const char* name;       // for test names
  const char* extension;  // with the dot
  std::string (*make)();
};

const SeedFile kSeeds[] = {
    {"Obj", ".obj", [] { return std::string(test::kObjTwoObjects); }},
    {"AsciiPly", ".ply", [] { return std::string(test::kPlyAscii); }},
    {"BinaryPly", ".ply", test::binaryPlyTetrahedron},
    {"AsciiStl", ".stl", [] { return std::string(test::kStlAscii); }},
    {"BinaryStl", ".stl", test::binaryStl},
    // The glTF files name this test as their asset's generator.
    {"Gltf", ".gltf", [] { return test::gltfEmbedded("logrid loader_fuzz_test"); }},
    {"Glb", ".glb", [] { return test::glbInstanced("logrid loader_fuzz_test"); }},
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

// Inputs per format: 1500, or LOGRID_FUZZ_INPUTS for a longer run.
int inputsPerFormat() {
  const char* text = std::getenv("LOGRID_FUZZ_INPUTS");
  const int inputs = text ? std::atoi(text) : 0;
  return inputs > 0 ? inputs : 1500;
}

// Mutates the seed file inputsPerFormat() times and loads each result.
void fuzz(const char* name) {
  const SeedFile& seed = *std::find_if(
      std::begin(kSeeds), std::end(kSeeds),
      [name](const SeedFile& candidate) { return std::strcmp(candidate.name, name) == 0; });
  const std::string valid = seed.make();
  const std::string path =
      test::tempFilePath("logrid_loader_fuzz", std::string(seed.name) + seed.extension);
  // Printed first: after a crash this file holds the input that caused it.
  std::printf("inputs are written to %s\n", path.c_str());
  std::fflush(stdout);

  // The unmutated file must load, or the mutations test nothing.
  test::writeBytes(path, valid);
  ASSERT_NO_THROW(validateScene(loadSceneFile(path)));

  std::uint64_t name_hash = 0xCBF29CE484222325ull;  // FNV-1a: the same everywhere
  for (const char* c = seed.name; *c != '\0'; ++c) {
    name_hash = (name_hash ^ static_cast<unsigned char>(*c)) * 0x100000001B3ull;
  }
  Rng rng(0x6C6F67726964ull ^ name_hash);
  Watchdog watchdog(std::chrono::seconds(20));
  int loaded = 0, refused = 0;
  // Warnings (files that bend their format but load) are counted, not printed.
  LoadOptions options;
  int warned = 0;
  options.warn = [&warned](const std::string&) { ++warned; };
  const int inputs = inputsPerFormat();
  for (int i = 0; i < inputs; ++i) {
    std::string input = valid;
    const std::size_t mutations = 1 + rng.below(4);
    for (std::size_t m = 0; m < mutations; ++m) mutateOnce(input, rng);
    test::writeBytes(path, input);
    const std::string what = path + " (input " + std::to_string(i) + ")";
    watchdog.arm(&what);
    try {
      const Scene scene = loadSceneFile(path, options);
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
  std::printf("%s: %d mutated inputs loaded, %d refused with logrid::Error, %d warnings\n",
              seed.name, loaded, refused, warned);
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
