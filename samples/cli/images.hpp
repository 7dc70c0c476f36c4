// PNG output through OpenImageIO, and the overlay pictures of LOG figures 1 and 5: the
// tile grid coloured by state, the border and internal tiles of a tested box, and the
// drawn objects' leaf boxes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/grid.hpp"
#include "logrid/projection.hpp"

namespace logrid::samples {

// rgba: width * height * 4 bytes, rows bottom-up (GL order). Throws logrid::Error
// (Environment) naming the path if it cannot be written.
void writePng(const std::string& path, const std::vector<std::uint8_t>& rgba, std::uint32_t width,
              std::uint32_t height);

// How the tiles are tinted.
enum class TileShade : std::uint8_t {
  States,  // occlusion state: full red, partial yellow, free clear (LOG §3)
  Zfar,    // the tile's farthest depth (LOG §4): near white to far blue, free clear
};

struct OverlayData {
  const OcclusionGrid* grid = nullptr;        // the grid at the end of the frame
  std::vector<BoxProjection> occluded;        // boxes the tests culled
  std::vector<BoxProjection> tested_visible;  // boxes the tests let through
  std::vector<Aabb> drawn_boxes;              // leaf boxes whose objects were drawn
  TileShade shade = TileShade::States;
  bool outline_visible = false;  // outline tested_visible in cyan (the viewer's box view)
};

// The frame, dimmed, with: tiles tinted red (full), yellow (partial) or left clear
// (free), or by their zfar, outdated tiles hatched in blue; red outlines for occluded
// boxes (and cyan ones for boxes tested visible, when asked); the internal (dark) and
// border (light) tiles of the largest occluded box, as in figure 1; and the drawn leaf
// boxes as green wireframes, as in figure 5.
std::vector<std::uint8_t> drawOverlay(const std::vector<std::uint8_t>& rgba, const Camera& camera,
                                      const OverlayData& data);

}  // namespace logrid::samples
