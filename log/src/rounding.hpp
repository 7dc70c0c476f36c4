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

// The least float >= v (roundUp) and the greatest float <= v (roundDown); NaN stays NaN.
// Without a branch on the value: whether v lies between two floats is a coin toss per
// value, and the projection rounds five values a box. f + 0 turns -0 into +0, whose
// next float up is the smallest subnormal, as from the bit pattern of any f >= +0 plus
// one; below zero the next float up is the bit pattern minus one. The step is added
// only where the float conversion rounded down.
inline float roundUp(double v) {
  const float f = static_cast<float>(v);
  const std::uint32_t step = static_cast<double>(f) < v;  // 0 or 1
  const float g = f + 0.0f;
  std::uint32_t bits_f, bits_g;
  std::memcpy(&bits_f, &f, sizeof bits_f);
  std::memcpy(&bits_g, &g, sizeof bits_g);
  const std::uint32_t up = bits_g + 1 - ((bits_g >> 31) << 1);  // nextUp(f)'s bits
  const std::uint32_t bits = bits_f + step * (up - bits_f);     // unsigned: wraps exactly
  float out;
  std::memcpy(&out, &bits, sizeof out);
  return out;
}

// roundDown(v) = -roundUp(-v): the conversion to float rounds to nearest, symmetric in
// the sign, and negation is exact.
inline float roundDown(double v) { return -roundUp(-v); }

}  // namespace logrid::detail
