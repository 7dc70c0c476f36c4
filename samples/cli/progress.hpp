// Progress of a long run on stderr: rewrites one line on a terminal, prints every ~10%
// otherwise (a log file).
#pragma once

#include <cstddef>
#include <string>

namespace logrid::samples {

class Progress {
 public:
  explicit Progress(std::string label, std::size_t total);
  void update(std::size_t done, double ms_per_frame);
  void finish();

 private:
  std::string label_;
  std::size_t total_;
  bool tty_;
  std::size_t last_percent_ = 0;
};

}  // namespace logrid::samples
