// The base of cpu/ and zread/'s sources that read pixels: logrid::PixelSource
// (logrid/pixel_source.hpp), under the name they have always used.
#pragma once

#include "logrid/pixel_source.hpp"

namespace logrid::cpu {

using PixelReader = logrid::PixelSource;

}  // namespace logrid::cpu
