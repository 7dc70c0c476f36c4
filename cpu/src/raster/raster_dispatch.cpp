// Which raster kernel runs: the widest the CPU reports, or the one asked for.
#include "raster/raster_triangle.hpp"

namespace logrid::cpu::detail {

RasterFunction rasterFunction(Isa isa) {
  switch (isa) {
    case Isa::Scalar: return rasterScalar;
#if LOGRID_CPU_X86
    case Isa::Sse41: return __builtin_cpu_supports("sse4.1") ? rasterSse41 : nullptr;
    case Isa::Avx2: return __builtin_cpu_supports("avx2") ? rasterAvx2 : nullptr;
#else
    case Isa::Sse41:
    case Isa::Avx2: return nullptr;
#endif
    case Isa::Auto: return rasterFunction(bestIsa());
  }
  return nullptr;
}

Isa bestIsa() {
#if LOGRID_CPU_X86
  if (__builtin_cpu_supports("avx2")) return Isa::Avx2;
  if (__builtin_cpu_supports("sse4.1")) return Isa::Sse41;
#endif
  return Isa::Scalar;
}

}  // namespace logrid::cpu::detail
