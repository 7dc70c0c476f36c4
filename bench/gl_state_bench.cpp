// What keeping the application's GL state costs a depth read (zread/gl_state.hpp): one
// 32 x 32 tile read through zread::ReadPixelsSource on a headless context, ns per read
// and GL state queries per read (counter "state_queries"), in three set-ups:
//   per_read   no access window: every read saves, checks and restores on its own (what
//              every read did before windows, and what a source used outside a culler
//              still does);
//   window/N   N reads in one access window (one Culler::nextBatch() holding N reads);
//   managed/N  GlStatePolicy::ApplicationManaged, N reads a window: nothing saved.
// On llvmpipe a query is a function call; on a threaded driver each one waits for the
// driver's thread, so the count is the figure that carries over. GL: the target is
// built only with LOGRID_BUILD_GL.
#include <benchmark/benchmark.h>

#include <cstdint>

#include "logrid/camera.hpp"
#include "logrid/gl/context.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/zread/gl_sources.hpp"

namespace logrid {
namespace {

constexpr std::uint32_t kSize = 256, kTile = 32;

gl::Context& context() {
  static gl::Context c;
  c.makeCurrent();
  return c;
}

void readTiles(benchmark::State& state, zread::GlStatePolicy policy, std::int64_t per_window) {
  context();
  gl::FramebufferDesc desc;
  desc.width = kSize;
  desc.height = kSize;
  gl::Framebuffer fb(desc);
  const float black[4] = {0, 0, 0, 1};
  fb.clear(black);
  Camera camera;
  camera.width = kSize;
  camera.height = kSize;
  zread::ReadPixelsSource source(fb.handle(), policy);
  orThrow(source.beginFrame(camera));
  AreaRequest request;
  AreaAnswer answer;
  std::int64_t reads = 0;
  const std::uint64_t before = source.counters().state_queries;
  for (auto _ : state) {
    if (per_window > 0) source.beginAccess();
    const std::int64_t n = per_window > 0 ? per_window : 1;
    for (std::int64_t i = 0; i < n; ++i, ++reads) {
      const std::int32_t t = std::int32_t(reads % 64);
      request.rect = {(t % 8) * std::int32_t(kTile), (t / 8) * std::int32_t(kTile),
                      (t % 8 + 1) * std::int32_t(kTile), (t / 8 + 1) * std::int32_t(kTile)};
      source.submit(&request, 1, &answer);
      benchmark::DoNotOptimize(answer);
    }
    if (per_window > 0) orThrow(source.endAccess());
  }
  orThrow(source.endFrame());
  state.SetItemsProcessed(reads);
  state.counters["state_queries"] = benchmark::Counter(
      double(source.counters().state_queries - before) / double(reads ? reads : 1));
}

void BM_TileReadPerRead(benchmark::State& state) {
  readTiles(state, zread::GlStatePolicy::Restore, 0);
}
void BM_TileReadWindow(benchmark::State& state) {
  readTiles(state, zread::GlStatePolicy::Restore, state.range(0));
}
void BM_TileReadManaged(benchmark::State& state) {
  readTiles(state, zread::GlStatePolicy::ApplicationManaged, state.range(0));
}

BENCHMARK(BM_TileReadPerRead)->Name("gl_state/per_read");
BENCHMARK(BM_TileReadWindow)->Name("gl_state/window")->Arg(1)->Arg(8)->Arg(64);
BENCHMARK(BM_TileReadManaged)->Name("gl_state/managed")->Arg(1)->Arg(64);

}  // namespace
}  // namespace logrid
