// logrid_cpu_cull: the CPU side of culling with the CPU occlusion buffer, without GL —
// the walkthrough's frames culled with log-state or log-zfar while the draw callback
// only hands each drawn object to the buffer. What it measures is what the buffer and
// the traversal cost a frame on the CPU (no renderer, no flushes); it runs under perf and
// valgrind (no GL driver, no image libraries loaded).
//
//   logrid_cpu_cull [forest|city] [scale] [frames] [log-zfar|log-state] [mesh|model]
//                   [full|half|quarter] [threads] [repeats] [isa] [per-pixel|masked]
//                   [min pixels per occluder triangle] [occluder triangle budget]
//
// threads: OcclusionBufferDesc::threads (0 lazy in the caller, 1 binned in the caller,
// N the caller and N - 1 started threads). Each repetition prints the CPU time of the
// calling thread and of every thread of the process beside the wall time.
#include <time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "logrid/cpu/occlusion_buffer.hpp"
#include "logrid/culler.hpp"
#include "logrid/error.hpp"
#include "scene/generators.hpp"
#include "scene/occluders.hpp"
#include "scene/prepare.hpp"
#include "scene/view.hpp"

namespace {

// CPU time of the calling thread: on a shared machine it counts what this thread ran,
// not the time it waited for a core.
double cpuMs(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}
double threadCpuMs() { return cpuMs(CLOCK_THREAD_CPUTIME_ID); }
// CPU time of every thread of the process: the caller and the buffer's workers.
double processCpuMs() { return cpuMs(CLOCK_PROCESS_CPUTIME_ID); }

}  // namespace

int main(int argc, char** argv) {
  using namespace logrid;
  auto arg = [&](int i, const char* fallback) {
    return std::string(argc > i ? argv[i] : fallback);
  };
  try {
    const std::string scene_name = arg(1, "forest");
    const double scale = std::stod(arg(2, "1"));
    const std::size_t frames = std::stoul(arg(3, "30"));
    const auto method = parseMethod(arg(4, "log-zfar"));
    const auto occluders = samples::parseOccluderChoice(arg(5, "mesh"));
    cpu::OcclusionBufferDesc desc;
    const bool resolution_ok = cpu::parseResolution(arg(6, "full"), desc.resolution);
    desc.threads = std::uint32_t(std::stoul(arg(7, "0")));
    const int repeats = std::stoi(arg(8, "3"));
    const bool isa_ok = cpu::parseIsa(arg(9, "auto"), desc.isa);
    const bool representation_ok =
        cpu::parseRepresentation(arg(10, "per-pixel"), desc.representation);
    desc.min_pixels_per_triangle = std::stod(arg(11, "0"));
    desc.triangle_budget = std::uint32_t(std::stoul(arg(12, "0")));
    if (!method || !occluders || !resolution_ok || !isa_ok || !representation_ok || frames < 1 ||
        repeats < 1) {
      std::fprintf(stderr,
                   "usage: logrid_cpu_cull [forest|city] [scale] [frames] "
                   "[log-zfar|log-state] [mesh|model] [full|half|quarter] [threads] "
                   "[repeats] [auto|scalar|sse4.1|avx2] [per-pixel|masked] [pixels per triangle] "
                   "[triangle budget]\n");
      return 2;
    }
    samples::Scene scene =
        scene_name == "city" ? samples::makeCity({scale, 1}) : samples::makeForest({scale, 1});
    const bvh::BuildArgs args = samples::defaultBuildArgs(scene);
    const samples::PreparedScene prepared = samples::prepareScene(std::move(scene), args);
    const cpu::OccluderMeshes& meshes = samples::sceneOccluders(
        prepared, *occluders, methodInfo(*method).semantics == TestSemantics::OcclusionState);
    cpu::OcclusionBuffer buffer(meshes, desc);
    CullerDesc cd;
    cd.method = *method;
    Culler culler(cd);
    samples::ViewSettings view;
    view.near_plane = prepared.near_plane;
    view.far_plane = prepared.far_plane;
    std::printf(
        "%s scale %g, %s, %s occluders, %s %s, %u threads, %s kernel, %zu frames, occluders "
        "of >= %g pixels per triangle, budget %u triangles\n",
        scene_name.c_str(), scale, toString(*method), samples::toString(*occluders),
        cpu::toString(desc.resolution), cpu::toString(desc.representation), desc.threads,
        cpu::toString(buffer.isa()), frames, desc.min_pixels_per_triangle, desc.triangle_budget);
    for (int rep = 0; rep < repeats; ++rep) {
      const cpu::OcclusionBufferStats before = buffer.stats();
      double ms = 0, cpu_ms = 0, process_ms = 0, objects = 0, boxes_tested = 0, boxes_occluded = 0;
      for (std::size_t f = 0; f < frames; ++f) {
        const Camera cam =
            samples::makeCamera(prepared.path.frame(f, frames), prepared.origin, view);
        const double cpu_start = threadCpuMs(), process_start = processCpuMs();
        const auto start = std::chrono::steady_clock::now();
        const FrameStats s = culler.cullFrame(cam, prepared.hierarchy, buffer,
                                              [&](ObjectId id) { buffer.drawObject(id); });
        ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                  .count();
        cpu_ms += threadCpuMs() - cpu_start;
        process_ms += processCpuMs() - process_start;
        objects += double(s.objects_drawn);
        boxes_tested += double(s.boxes_tested);
        boxes_occluded += double(s.boxes_occluded);
      }
      const cpu::OcclusionBufferStats& after = buffer.stats();
      const double n = double(frames);
      std::printf(
          "  cull %.3f ms/frame wall, %.3f ms CPU of this thread, %.3f of all threads (buffer "
          "%.3f wall, waiting "
          "%.3f, workers %.3f), %.1f objects, %.0f triangles set up, %.0f triangle-tiles in "
          "%.0f tiles; %.1f occluders left out (%.0f triangles selected); %.1f boxes tested, "
          "%.1f found occluded\n",
          ms / n, cpu_ms / n, process_ms / n, (after.seconds - before.seconds) * 1e3 / n,
          (after.wait_seconds - before.wait_seconds) * 1e3 / n,
          (after.worker_seconds - before.worker_seconds) * 1e3 / n, objects / n,
          double(after.triangles_set_up - before.triangles_set_up) / n,
          double(after.triangles_rasterized - before.triangles_rasterized) / n,
          double(after.tiles_rasterized - before.tiles_rasterized) / n,
          double(after.objects_unselected - before.objects_unselected) / n,
          double(after.triangles_selected - before.triangles_selected) / n, boxes_tested / n,
          boxes_occluded / n);
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "logrid_cpu_cull: %s\n", e.what());
    return 2;
  }
  return 0;
}
