// Directed rounding of doubles to float, for bounds that must stay bounds.
#pragma once

#include <cmath>
#include <limits>

namespace logrid::detail {

inline float roundDown(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

inline float roundUp(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

}  // namespace logrid::detail
