// Directed rounding of doubles to float, for bounds that must stay bounds.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace logrid::detail {

// The next float towards -infinity (nextDown) or +infinity (nextUp) of a non-NaN f, as
// std::nextafter gives it, without the library call (the projection rounds every box):
// floats of one sign are ordered as their bit patterns, and the zeros step to the
// smallest subnormal of the direction's sign.
inline float nextDown(float f) {
  if (f == 0) return -std::numeric_limits<float>::denorm_min();
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  bits = f > 0 ? bits - 1 : bits + 1;
  std::memcpy(&f, &bits, sizeof bits);
  return f;
}

inline float nextUp(float f) { return -nextDown(-f); }

inline float roundDown(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) > v ? nextDown(f) : f;
}

inline float roundUp(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) < v ? nextUp(f) : f;
}

}  // namespace logrid::detail
