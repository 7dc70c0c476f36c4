// What a person can change while the viewer runs. CullSettings go into the frame
// runner's configuration: a change rebuilds the runner (framebuffer, depth reader,
// culler) before the next frame. DisplaySettings only change what is drawn over it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cli/frame_runner.hpp"
#include "cli/images.hpp"

namespace logrid::viewer {

struct CullSettings {
  std::string method = "log-state";   // a name of methodChoices()
  std::string reader = "readpixels";  // a name of samples::readerTable()
  std::uint32_t tile = 32;
  DepthFormat format = DepthFormat::D32F;
  DepthConvention convention = DepthConvention::Standard;
  std::uint32_t lookahead = 1;  // or kUnlimitedLookahead
  bool coherence = false;
  GridApproximation approximation;
  bool verify = false;  // object-ID check every frame

  bool operator==(const CullSettings& o) const;
  bool operator!=(const CullSettings& o) const { return !(*this == o); }
};

// The knobs of `approximation` that `method` takes (MethodInfo::takes); the others are
// left at their exact values, as the panel shows them disabled for that method.
GridApproximation effectiveApproximation(const std::string& method,
                                         const GridApproximation& approximation);

// The settings a run configuration holds.
CullSettings settingsOf(const samples::RunConfig& config);
// `base` with the settings applied (the approximation as effectiveApproximation()), for
// a drawable of width x height pixels. Throws logrid::Error(InvalidArgument) for an
// unknown method or settings the culler refuses.
samples::RunConfig configFor(const samples::RunConfig& base, const CullSettings& settings,
                             std::uint32_t width, std::uint32_t height);
// One line: "method log-state, reader readpixels, tile 32, depth 32f standard, ...",
// with the approximation in effect.
std::string describe(const CullSettings& settings);

// Every method a frame runner takes, in the order of logrid's method table, then the
// oracle (methods added to the table appear here without a change).
std::vector<std::string> methodChoices();
// The next (step 1) or previous (step -1) entry of a list, wrapping around.
std::string cycle(const std::vector<std::string>& list, const std::string& current, int step);
std::vector<std::string> readerChoices();

enum class ShadeChoice : std::uint8_t {
  Auto,    // zfar for methods that test by depth, occlusion states for the others
  States,  // free / partial / full
  Zfar,    // the tiles' farthest depth
};

struct DisplaySettings {
  bool grid = false;  // tile-grid overlay
  ShadeChoice shade = ShadeChoice::Auto;
  bool boxes = false;  // tested boxes by answer and drawn leaf boxes
  bool top_view = false;
  bool panel = true;
  bool help = false;
};

// The overlay's shading for a method (ShadeChoice::Auto resolved).
samples::TileShade shadeFor(ShadeChoice choice, const std::string& method);

}  // namespace logrid::viewer
