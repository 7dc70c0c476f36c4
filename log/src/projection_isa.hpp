// Which instruction set Projector's batch calls run (projection.cpp, "The batch
// kernels"): the widest this CPU has, or one a test asks for.
#pragma once

#include <cstdint>

namespace logrid::detail {

enum class ProjectionIsa : std::uint8_t {
  Baseline,  // what the build targets (SSE2 on x86-64); every build has it
  Avx2,      // x86-64 with GCC only, where the CPU reports AVX2
};

// The set the batch calls run now: the forced one, else the widest available.
ProjectionIsa projectionIsa();
// Whether this build and this CPU can run `isa`.
bool projectionIsaAvailable(ProjectionIsa isa);
// For tests: run `isa` from now on (false, and nothing changed, where it is not
// available); resetProjectionIsa() goes back to the widest. Not to be called while
// another thread projects.
bool forceProjectionIsa(ProjectionIsa isa);
void resetProjectionIsa();

}  // namespace logrid::detail
