// The `cpu` reader (readers.cpp): the conservative CPU occlusion buffer
// (logrid/cpu/occlusion_buffer.hpp) fed, for each object the renderer draws, with its
// occluder (scene/occluders.hpp), so the grid culls without reading the GL depth buffer.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "cli/readers.hpp"
#include "logrid/cpu/occlusion_buffer.hpp"
#include "scene/occluders.hpp"

namespace logrid::samples {

struct CpuReaderOptions {
  cpu::Resolution resolution = cpu::Resolution::Full;
  cpu::Representation representation = cpu::Representation::PerPixel;
  OccluderChoice occluders = OccluderChoice::Mesh;
  std::uint32_t threads = 0;  // worker threads of the buffer
  cpu::Isa isa = cpu::Isa::Auto;
  double min_pixels_per_triangle = 0;  // occluder selection (OcclusionBufferDesc)
  std::uint32_t triangle_budget = 0;
};

// What the buffer did in one frame.
struct CpuFrameStats {
  double ms = 0;                     // caller's time inside the buffer (draw notes, requests)
  double wait_ms = 0;                // of which waiting for workers
  double worker_ms = 0;              // workers' time
  std::uint64_t objects = 0;         // objects whose triangles were set up
  std::uint64_t triangles = 0;       // triangles set up
  std::uint64_t tile_triangles = 0;  // triangle-tile pairs rasterised
  std::uint64_t tiles = 0;           // tiles rasterised
  std::uint64_t fallbacks = 0;       // models replaced by their object's mesh
  std::uint64_t unselected = 0;      // drawn objects the occluder selection left out
  std::uint64_t moved = 0;           // moving objects handed over with their transform
};

class CpuFrameReader final : public FrameReader {
 public:
  // Throws logrid::Error for options this machine cannot run. `method`: the culler's
  // (occlusion-state methods get models within their objects' boxes, occluders.hpp).
  // `motion`: the movers' transforms of the frame being drawn (nullptr: none move).
  CpuFrameReader(const PreparedScene& scene, const CpuReaderOptions& options,
                 const ProjectionSettings& projection, Method method,
                 const MotionFrame* motion = nullptr);
  DepthSource& source() override { return *buffer_; }
  // Moving objects (ids from PreparedScene::static_objects on) are rasterised where the
  // frame draws them: their own mesh placed by the frame's transform of that id
  // (MotionFrame::transforms[id - static_objects]). One without a transform (no motion
  // frame given) is left out, which only loses occlusion.
  void objectDrawn(ObjectId id) override;
  // The counts since the previous call.
  CpuFrameStats takeFrameStats();

 private:
  std::unique_ptr<cpu::OcclusionBuffer> buffer_;
  cpu::OcclusionBufferStats last_;
  ObjectId static_objects_;
  const MotionFrame* motion_;
};

std::unique_ptr<FrameReader> makeCpuReader(const ReaderContext& context);

}  // namespace logrid::samples
