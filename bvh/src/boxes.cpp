#include "boxes.hpp"

#include <cmath>
#include <sstream>

namespace logrid::bvh::detail {

Status checkBox(const char* who, std::size_t id, const Aabb& b) {
  const bool finite = std::isfinite(b.min.x) && std::isfinite(b.min.y) && std::isfinite(b.min.z) &&
                      std::isfinite(b.max.x) && std::isfinite(b.max.y) && std::isfinite(b.max.z);
  if (finite && b.min.x <= b.max.x && b.min.y <= b.max.y && b.min.z <= b.max.z) return {};
  std::ostringstream out;
  out << who << ": object " << id << " has an invalid box (min " << b.min.x << " " << b.min.y << " "
      << b.min.z << ", max " << b.max.x << " " << b.max.y << " " << b.max.z
      << "); boxes must be finite with min <= max";
  return Status(ErrorCode::BadInput, out.str());
}

}  // namespace logrid::bvh::detail
