#include "cli/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace logrid::samples {

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)), total_(total), tty_(isatty(STDERR_FILENO) != 0) {}

void Progress::update(std::size_t done, double ms) {
  if (tty_) {
    std::fprintf(stderr, "\r%s: frame %zu/%zu, %.2f ms/frame   ", label_.c_str(), done, total_, ms);
    std::fflush(stderr);
    return;
  }
  const std::size_t percent = done * 100 / std::max<std::size_t>(total_, 1);
  if (done == total_ || percent >= last_percent_ + 10) {
    last_percent_ = percent;
    std::fprintf(stderr, "%s: frame %zu/%zu, %.2f ms/frame\n", label_.c_str(), done, total_, ms);
  }
}

void Progress::finish() {
  if (tty_) std::fprintf(stderr, "\n");
}

}  // namespace logrid::samples
