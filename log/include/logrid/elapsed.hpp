// Elapsed time as logrid's statistics report it (FrameStats::seconds, read_seconds, the
// hierarchies' update and build times): wall-clock time on the steady clock, in double.
#pragma once

#include <chrono>

namespace logrid {

// Seconds since `start` (a std::chrono::steady_clock::now() of the caller).
inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Milliseconds since `start`.
inline double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace logrid
