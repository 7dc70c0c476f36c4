// The directional discretized occluders as the culler's occluder pre-pass
// (logrid/occluder_source.hpp), for the methods ddo and ddo+log (method.hpp). Each frame
// the selector (selector.hpp) walks the octree for the camera and selects the faces
// valid for the viewpoint:
//   * ddo: boxes are tested against the selector's CPU occlusion map; nothing is drawn;
//   * ddo+log: of the merged occluder quads, those that pay (OccluderBudget) are handed
//     to the culler with their outlines (drawnQuads()), which records the grid cells they
//     cover entirely as hidden behind them without a read (coverage.hpp, grid.hpp).
//     Nothing is drawn: the scene's own geometry covers them (occluder_source.hpp). With
//     a drawer (a GL application: gl::OccluderRenderer, depth only) the pass also draws
//     them into the application's depth buffer and announces their pixels and farthest
//     keys, which the culler then treats as drawn out of order (measured slower: their
//     tiles are outdated and boxes in front of them are tested by depth, docs/DDO.md).
// The octree holds the static objects it was built from; boxes of anything else (moving
// objects) are tested against the same occluders, which only say where static geometry
// hides everything behind.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "logrid/ddo/selector.hpp"
#include "logrid/error.hpp"
#include "logrid/occluder_source.hpp"

namespace logrid::ddo {

// Which of the selected occluders ddo+log records. An occluder pays through the grid tiles
// it fills: each is recorded hidden behind it without a read (coverage.hpp), so every
// box behind it there is culled from the record. One that fills no tile costs its
// recording and hides only the boxes whose rectangle meets no other cell of a tile. So
// the pass hands over the occluders that fill at least `min_tiles` tiles of the culler's
// grid, most tiles first (screen area that counts), the nearer far key first among equals
// (a nearer occluder hides more of the scene), up to `max_triangles` (two a quad).
struct OccluderBudget {
  std::uint32_t max_triangles = 512;  // occluder triangles chosen per frame at most
  std::uint32_t tile_size = 32;       // the culler's grid tile side (CullerDesc::tile_size)
  std::uint32_t min_tiles = 1;        // tiles an occluder must fill; 0: every selected
                                      // occluder is drawn (up to the cap), as before
};

// What the pass did in its last frame.
struct OccluderPassStats {
  std::uint64_t candidates = 0;    // occluders selected after merging
  std::uint64_t drawn = 0;         // of those, chosen (ddo+log; drawn with a drawer)
  std::uint64_t tiles_filled = 0;  // tiles the chosen ones fill (by the budget's tile size)
};

class OccluderPass final : public OccluderSource {
 public:
  // Draws `occluders` into the application's depth buffer for `camera` (depth only, with
  // the depth test that keeps the nearer fragment). Returns what failed, if anything
  // (gl::OccluderRenderer::tryDraw's Status); beginFrame() returns it. Optional.
  using Drawer =
      std::function<Status(const std::vector<Occluder>& occluders, const Camera& camera)>;

  // `octree` must outlive the pass. Without a drawer nothing is drawn (ddo, and ddo+log's
  // recorded occluders).
  explicit OccluderPass(const Octree& octree, Drawer drawer = {},
                        const SelectorSettings& settings = {}, const OccluderBudget& budget = {});

  // Selects for `camera`; returns the faces selected into the map, or, with `record`, the
  // occluders chosen (those that pay, OccluderBudget; drawn if the pass has a drawer).
  // Fails with ErrorCode::InvalidArgument for an invalid camera (Selector::trySelect),
  // and with the drawer's error.
  Result<std::uint64_t> beginFrame(const Camera& camera, const ProjectionSettings& projection,
                                   bool record, std::vector<DrawnArea>& drawn) override;
  bool occludes(const PixelRect& rect, float threshold) const override;
  const std::vector<DrawnQuad>& drawnQuads() const override { return quads_; }

  // The last frame's selection (occluders(), map()), what it chose, and what it did.
  const Selector& selector() const { return selector_; }
  const std::vector<Occluder>& drawn() const { return drawn_; }
  const SelectionStats& stats() const { return stats_; }
  const OccluderPassStats& passStats() const { return pass_stats_; }
  const OccluderBudget& budget() const { return budget_; }

 private:
  void choose(const Camera& camera, const ProjectionSettings& projection);

  Selector selector_;
  Drawer drawer_;
  OccluderBudget budget_;
  SelectionStats stats_;
  OccluderPassStats pass_stats_;
  std::vector<Occluder> drawn_;
  std::vector<DrawnQuad> quads_;
  struct Candidate {
    std::uint32_t index;
    std::uint32_t tiles;
    float far_key;
  };
  std::vector<Candidate> candidates_;
};

}  // namespace logrid::ddo
