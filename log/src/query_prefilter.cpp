#include "query_prefilter.hpp"

namespace logrid::detail {

std::optional<Visibility> GridPrefilter::decide(const BoxProjection& p) {
  const std::optional<Visibility> v = grid_.decide(p.rect, p.occlusionThreshold(), counts_);
  if (!v) wanted_.push_back(p.rect);
  return v;
}

void GridPrefilter::refresh() {
  if (wanted_.empty()) return;
  grid_.refreshUnder(wanted_, counts_);
  wanted_.clear();
}

}  // namespace logrid::detail
