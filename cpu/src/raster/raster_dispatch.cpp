// Which raster kernel runs: the widest the CPU reports, or the one asked for.
#include "raster/raster_triangle.hpp"

namespace logrid::cpu::detail {

Kernels kernels(Isa isa) {
  switch (isa) {
    case Isa::Scalar: return {rasterScalar, rangeScalar, maskedScalar};
#if LOGRID_CPU_X86
    case Isa::Sse41:
      if (__builtin_cpu_supports("sse4.1")) return {rasterSse41, rangeSse41, maskedSse41};
      return {};
    case Isa::Avx2:
      if (__builtin_cpu_supports("avx2")) return {rasterAvx2, rangeAvx2, maskedAvx2};
      return {};
#else
    case Isa::Sse41:
    case Isa::Avx2: return {};
#endif
    case Isa::Auto: return kernels(bestIsa());
  }
  return {};
}

Isa bestIsa() {
#if LOGRID_CPU_X86
  if (__builtin_cpu_supports("avx2")) return Isa::Avx2;
  if (__builtin_cpu_supports("sse4.1")) return Isa::Sse41;
#endif
  return Isa::Scalar;
}

}  // namespace logrid::cpu::detail
