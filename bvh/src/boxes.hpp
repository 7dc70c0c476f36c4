// Box helpers the hierarchies of bvh/ share (FlatHierarchy, TernaryTree). Internal to
// logrid::bvh.
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>

#include "logrid/error.hpp"
#include "logrid/types.hpp"

namespace logrid::bvh::detail {

constexpr float kInf = std::numeric_limits<float>::infinity();

// The box that grow() makes into any other: min +inf, max -inf.
inline Aabb emptyBox() { return {{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}}; }

// a becomes the smallest box holding a and b.
inline void grow(Aabb& a, const Aabb& b) {
  a.min.x = std::min(a.min.x, b.min.x), a.min.y = std::min(a.min.y, b.min.y);
  a.min.z = std::min(a.min.z, b.min.z), a.max.x = std::max(a.max.x, b.max.x);
  a.max.y = std::max(a.max.y, b.max.y), a.max.z = std::max(a.max.z, b.max.z);
}

// ErrorCode::BadInput naming `who` and object `id` unless `b` is finite with min <= max
// on every axis.
Status checkBox(const char* who, std::size_t id, const Aabb& b);

}  // namespace logrid::bvh::detail
