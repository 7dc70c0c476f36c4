// The directional discretized occluders as the culler's occluder pre-pass
// (logrid/occluder_source.hpp), for the methods ddo and ddo+log (method.hpp). Each frame
// the selector (selector.hpp) walks the octree for the camera and selects the faces
// valid for the viewpoint:
//   * ddo: boxes are tested against the selector's CPU occlusion map; nothing is drawn;
//   * ddo+log: of the merged occluder quads, those that pay (OccluderBudget) are drawn
//     into the application's depth buffer by its drawer (a GL application:
//     gl::OccluderRenderer, depth only) and announced with their pixels and farthest
//     keys, and with their outlines (drawnQuads()), so that the culler records the grid
//     tiles they cover entirely as full without reading them (coverage.hpp).
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

// Which of the selected occluders ddo+log draws. An occluder pays through the grid tiles
// it fills: each is recorded full without a read (coverage.hpp), so every box behind it
// there is culled from the record. One that fills no tile only costs: a draw, and the
// tiles it touches become outdated, to be read by the next test over them. So the pass
// draws the occluders that fill at least `min_tiles` tiles of the culler's grid, most
// tiles first (screen area that counts), the nearer far key first among equals (a nearer
// occluder hides more of the scene), until `max_triangles` (two a quad) are drawn.
struct OccluderBudget {
  std::uint32_t max_triangles = 512;  // occluder triangles drawn per frame at most
  std::uint32_t tile_size = 32;       // the culler's grid tile side (CullerDesc::tile_size)
  std::uint32_t min_tiles = 1;        // tiles an occluder must fill; 0: every selected
                                      // occluder is drawn (up to the cap), as before
};

// What the pass did in its last frame.
struct OccluderPassStats {
  std::uint64_t candidates = 0;    // occluders selected after merging
  std::uint64_t drawn = 0;         // of those, drawn (ddo+log)
  std::uint64_t tiles_filled = 0;  // tiles the drawn ones fill (by the budget's tile size)
};

class OccluderPass final : public OccluderSource {
 public:
  // Draws `occluders` into the application's depth buffer for `camera` (depth only, with
  // the depth test that keeps the nearer fragment). Returns what failed, if anything
  // (gl::OccluderRenderer::tryDraw's Status); beginFrame() returns it.
  using Drawer =
      std::function<Status(const std::vector<Occluder>& occluders, const Camera& camera)>;

  // `octree` must outlive the pass. Without a drawer the pass serves ddo only.
  explicit OccluderPass(const Octree& octree, Drawer drawer = {},
                        const SelectorSettings& settings = {}, const OccluderBudget& budget = {});

  // Selects for `camera`; returns the faces selected into the map, or, with `draw`, the
  // occluders drawn (those that pay, OccluderBudget). Fails with
  // ErrorCode::InvalidArgument for an invalid camera (Selector::trySelect) or when asked
  // to draw without a drawer, and with the drawer's error.
  Result<std::uint64_t> beginFrame(const Camera& camera, const ProjectionSettings& projection,
                                   bool draw, std::vector<DrawnArea>& drawn) override;
  bool occludes(const PixelRect& rect, float threshold) const override;
  const std::vector<DrawnQuad>& drawnQuads() const override { return quads_; }

  // The last frame's selection (occluders(), map()), what it drew, and what it did.
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
