// What the libFuzzer targets share: a check that aborts with a message (libFuzzer then
// keeps the input as a crash; the replay test fails), and the entry point every target
// defines. Targets are built twice: with clang and -fsanitize=fuzzer by scripts/fuzz.sh,
// and with the normal compiler into a replay program (replay_main.cpp) that the `fuzz`
// ctest label runs over the target's corpus in tests/fuzz/corpus/<target>/.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

#define LOGRID_FUZZ_CHECK(condition, ...)                                                       \
  do {                                                                                          \
    if (!(condition)) {                                                                         \
      std::fprintf(stderr, "%s:%d: fuzz check failed: %s\n  ", __FILE__, __LINE__, #condition); \
      std::fprintf(stderr, __VA_ARGS__);                                                        \
      std::fprintf(stderr, "\n");                                                               \
      std::abort();                                                                             \
    }                                                                                           \
  } while (0)

namespace logrid::fuzz {

// Reads fixed-size values from the front of a fuzz input; past its end every value is 0,
// so every input decodes to something.
class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::size_t left() const { return size_ - at_; }
  const std::uint8_t* rest() const { return data_ + at_; }
  std::uint8_t byte() { return at_ < size_ ? data_[at_++] : 0; }
  std::uint16_t u16() { return std::uint16_t(byte() | (byte() << 8)); }
  std::uint32_t u32() { return std::uint32_t(u16()) | (std::uint32_t(u16()) << 16); }
  // A value in [lo, hi] from 16 bits.
  double range(double lo, double hi) { return lo + (hi - lo) * double(u16()) / 65535.0; }
  // Any float bit pattern, NaN and infinities included.
  float anyFloat() {
    const std::uint32_t bits = u32();
    float f;
    __builtin_memcpy(&f, &bits, sizeof f);
    return f;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
};

// One scratch directory per process for the targets that read files (`name` tells the
// targets apart), removed at exit.
struct ScratchDir {
  std::filesystem::path dir;
  explicit ScratchDir(const char* name)
      : dir(std::filesystem::temp_directory_path() /
            (std::string("logrid_") + name + "." + std::to_string(::getpid()))) {
    std::filesystem::create_directories(dir);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
};

}  // namespace logrid::fuzz
