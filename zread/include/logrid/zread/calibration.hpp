// The hardware parameters of Guthe et al.'s cost model (NOHC §3.2, Table 2), measured on
// the current GL context as the paper's §3.2.2 describes: a mesh of many triangles (O+)
// and one of two (O-), drawn pixel-sized for the per-call and per-triangle times and
// full-screen for the per-fragment time; occlusion queries of a pixel-sized and a
// screen-filling box (through BoxQuerySource, as the culler issues them) for the query's
// setup and per-fragment times; the time until a single query on an idle pipeline answers
// (latency: the paper takes the largest of several, here the median, since the largest
// on a shared machine is a scheduling hiccup); a query around each draw against none
// (overhead); and an availability poll of a query with work pending (the paper's "is the
// API's synchronisation reasonably fast", §4.3). Each time is the median of `repeats`
// runs, wall-clock between glFinish calls. Materials are not told apart: one flat-shaded
// material.
//
// The measurement draws into a framebuffer of its own (`size` x `size`, RGBA8 and 32-bit
// float depth), takes a few seconds on llvmpipe with 2 cores, and restores the bindings
// and state it changes. Needs a current GL 4.5 context.
#pragma once

#include <cstdint>
#include <string>

#include "logrid/error.hpp"
#include "logrid/query_schedule.hpp"

namespace logrid::zread {

struct CalibrationDesc {
  std::uint32_t size = 512;   // side of the framebuffer measured in, pixels
  std::uint32_t repeats = 5;  // runs per time; the median is kept
};

// Both forms of each (logrid/error.hpp): an invalid description is InvalidArgument, a
// driver that cannot render the measurement's framebuffer Environment.
Result<HardwareParameters> tryMeasureHardwareParameters(const CalibrationDesc& desc = {});
HardwareParameters measureHardwareParameters(const CalibrationDesc& desc = {});

// The parameters of the current context's renderer (its GL_RENDERER string), measured
// with the default description on the first call for each renderer and kept in memory
// for the rest of the process (no file: a driver update or another GPU measures afresh).
Result<HardwareParameters> tryHardwareParameters();
HardwareParameters hardwareParameters();

// GL_RENDERER of the current context.
std::string rendererName();

#if LOGRID_HAS_EXCEPTIONS
inline HardwareParameters measureHardwareParameters(const CalibrationDesc& desc) {
  return logrid::orThrow(tryMeasureHardwareParameters(desc));
}
inline HardwareParameters hardwareParameters() { return logrid::orThrow(tryHardwareParameters()); }
#endif

}  // namespace logrid::zread
