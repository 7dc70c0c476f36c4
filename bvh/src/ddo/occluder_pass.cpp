#include "logrid/ddo/occluder_pass.hpp"

#include <algorithm>

namespace logrid::ddo {
namespace {

DrawnQuad quadOf(const Occluder& o) {
  DrawnQuad q;
  for (int i = 0; i < 4; ++i) q.window[i][0] = o.window[i][0], q.window[i][1] = o.window[i][1];
  q.near_key = o.near_key;
  q.far_key = o.far_key;
  return q;
}

// Tiles of a grid of `tile` pixels that the quad covers entirely.
std::uint32_t tilesFilled(const DrawnQuad& q, const PixelRect& rect, std::uint32_t tile,
                          const Camera& camera, const CoverageRule& rule) {
  if (rect.empty() || tile == 0) return 0;
  const QuadCoverage coverage(q, rule);
  std::uint32_t n = 0;
  const auto t = std::int32_t(tile);
  for (std::int32_t y = rect.y0 / t * t; y < rect.y1; y += t) {
    for (std::int32_t x = rect.x0 / t * t; x < rect.x1; x += t) {
      const PixelRect r{x, y, std::min(x + t, std::int32_t(camera.width)),
                        std::min(y + t, std::int32_t(camera.height))};
      n += coverage.covers(r) ? 1u : 0u;
    }
  }
  return n;
}

}  // namespace

OccluderPass::OccluderPass(const Octree& octree, Drawer drawer, const SelectorSettings& settings,
                           const OccluderBudget& budget)
    : selector_(octree, settings), drawer_(std::move(drawer)), budget_(budget) {}

Result<std::uint64_t> OccluderPass::beginFrame(const Camera& camera,
                                               const ProjectionSettings& projection, bool record,
                                               std::vector<DrawnArea>& drawn) {
  drawn_.clear();
  quads_.clear();
  pass_stats_ = {};
  if (Status s = selector_.trySelect(camera, {}, stats_, projection); !s) return s;
  pass_stats_.candidates = selector_.occluders().size();
  if (!record) return stats_.faces_selected;
  choose(camera, projection);
  if (drawer_ && !drawn_.empty()) {
    if (Status s = drawer_(drawn_, camera); !s) return s;
    for (const Occluder& o : drawn_) drawn.push_back({o.rect, o.far_key});
  }
  for (const Occluder& o : drawn_) quads_.push_back(quadOf(o));
  pass_stats_.drawn = drawn_.size();
  return drawn_.size();
}

void OccluderPass::choose(const Camera& camera, const ProjectionSettings& projection) {
  const std::vector<Occluder>& all = selector_.occluders();
  const CoverageRule rule = coverageRule(camera, projection);
  candidates_.clear();
  for (std::size_t i = 0; i < all.size(); ++i) {
    const std::uint32_t tiles =
        tilesFilled(quadOf(all[i]), all[i].rect, budget_.tile_size, camera, rule);
    if (tiles < budget_.min_tiles) continue;
    candidates_.push_back({std::uint32_t(i), tiles, all[i].far_key});
  }
  // Most tiles first; among equals the nearer (it hides more of the scene behind it);
  // then selection order, so that the choice does not depend on the sort.
  std::sort(candidates_.begin(), candidates_.end(), [](const Candidate& a, const Candidate& b) {
    if (a.tiles != b.tiles) return a.tiles > b.tiles;
    if (a.far_key != b.far_key) return a.far_key < b.far_key;
    return a.index < b.index;
  });
  const std::size_t most = budget_.max_triangles / 2;
  if (candidates_.size() > most) candidates_.resize(most);
  for (const Candidate& c : candidates_) {
    drawn_.push_back(all[c.index]);
    pass_stats_.tiles_filled += c.tiles;
  }
}

bool OccluderPass::occludes(const PixelRect& rect, float threshold) const {
  return selector_.map().occludes(rect, threshold);
}

}  // namespace logrid::ddo
