#include "cli/cpu_reader.hpp"

#include <algorithm>
#include <iterator>

namespace logrid::samples {

CpuFrameReader::CpuFrameReader(const PreparedScene& scene, const CpuReaderOptions& options,
                               const ProjectionSettings& projection, Method method,
                               const MotionFrame* motion)
    : static_objects_(scene.static_objects), motion_(motion) {
  cpu::OcclusionBufferDesc desc;
  desc.resolution = options.resolution;
  desc.representation = options.representation;
  desc.isa = options.isa;
  desc.threads = options.threads;
  desc.min_pixels_per_triangle = options.min_pixels_per_triangle;
  desc.triangle_budget = options.triangle_budget;
  desc.projection = projection;
  buffer_ = std::make_unique<cpu::OcclusionBuffer>(
      sceneOccluders(scene, options.occluders,
                     methodInfo(method).semantics == TestSemantics::OcclusionState),
      desc);
  last_ = buffer_->stats();
}

void CpuFrameReader::objectDrawn(ObjectId id) {
  if (id < static_objects_) {
    buffer_->drawObject(id);
    return;
  }
  // Per moving ObjectId: its transform, as FrameRunner::applyMotion gives the renderer.
  const std::size_t mover = id - static_objects_;
  if (!motion_ || mover >= motion_->transforms.size()) return;
  const RigidTransform& r = motion_->transforms[mover];
  cpu::ObjectTransform t;
  std::copy(std::begin(r.rotation), std::end(r.rotation), t.rotation);
  t.translation = r.translation;
  buffer_->drawObject(id, t);
}

CpuFrameStats CpuFrameReader::takeFrameStats() {
  const cpu::OcclusionBufferStats& now = buffer_->stats();
  CpuFrameStats f;
  f.ms = (now.seconds - last_.seconds) * 1e3;
  f.wait_ms = (now.wait_seconds - last_.wait_seconds) * 1e3;
  f.worker_ms = (now.worker_seconds - last_.worker_seconds) * 1e3;
  f.objects = now.objects_set_up - last_.objects_set_up;
  f.triangles = now.triangles_set_up - last_.triangles_set_up;
  f.tile_triangles = now.triangles_rasterized - last_.triangles_rasterized;
  f.tiles = now.tiles_rasterized - last_.tiles_rasterized;
  f.fallbacks = now.objects_fallback - last_.objects_fallback;
  f.unselected = now.objects_unselected - last_.objects_unselected;
  f.moved = now.objects_moved - last_.objects_moved;
  last_ = now;
  return f;
}

std::unique_ptr<FrameReader> makeCpuReader(const ReaderContext& c) {
  return std::make_unique<CpuFrameReader>(c.scene, c.cpu ? *c.cpu : CpuReaderOptions{},
                                          c.projection, c.method, c.motion);
}

}  // namespace logrid::samples
