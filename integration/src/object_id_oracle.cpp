#include "logrid/gl/object_id_oracle.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

#include "logrid/error.hpp"
#include "logrid/gl/context.hpp"
#include "logrid/projection.hpp"

namespace logrid::gl {

std::vector<ObjectId> OracleFrame::missedBy(const std::vector<ObjectId>& drawn) const {
  std::vector<ObjectId> sorted = drawn;
  std::sort(sorted.begin(), sorted.end());
  std::vector<ObjectId> missed;
  for (const ObjectId id : visible) {
    if (!std::binary_search(sorted.begin(), sorted.end(), id)) missed.push_back(id);
  }
  return missed;
}

namespace {

// The framebuffer is one the ID pass can draw the camera's frame into.
Status checkFramebuffer(const Framebuffer& framebuffer, const Camera& camera) {
  const FramebufferDesc& fb = framebuffer.desc();
  if (!fb.object_ids) {
    return Status(ErrorCode::InvalidArgument,
                  "objectIdOracle: the framebuffer has no object-ID attachment; create it with "
                  "FramebufferDesc::object_ids = true");
  }
  if (fb.width != camera.width || fb.height != camera.height ||
      fb.depth.convention != camera.depth.convention ||
      fb.depth.clip_range != camera.depth.clip_range || fb.depth.format != camera.depth.format) {
    std::ostringstream out;
    auto describe = [&out](std::uint32_t w, std::uint32_t h, const DepthSetup& d) {
      out << w << "x" << h << ", " << toString(d.convention) << " depth, " << toString(d.clip_range)
          << ", format " << toString(d.format);
    };
    out << "objectIdOracle: the framebuffer (";
    describe(fb.width, fb.height, fb.depth);
    out << ") does not match the camera (";
    describe(camera.width, camera.height, camera.depth);
    out << "); create it for the camera's viewport and depth set-up";
    return Status(ErrorCode::InvalidArgument, out.str());
  }
  return {};
}

Result<OracleFrame> idPass(const Framebuffer& framebuffer, const Projector& projector,
                           const std::vector<Aabb>& object_boxes,
                           const std::function<void()>& draw_ids) {
  const Camera& camera = projector.camera();
  framebuffer.bind();
  framebuffer.unmask();  // whatever a depth source left set: the whole frame's IDs
  framebuffer.clearDepthAndIds();
  framebuffer.selectIdPass(true);
  draw_ids();
  framebuffer.selectIdPass(false);
  const Result<std::vector<std::uint32_t>> read_ids = framebuffer.tryReadObjectIds();
  if (!read_ids) return read_ids.status();
  const Result<std::vector<float>> read_depth = framebuffer.tryReadDepth();
  if (!read_depth) return read_depth.status();
  const std::vector<std::uint32_t>& ids = read_ids.value();
  const std::vector<float>& depth = read_depth.value();
  if (Status s = tryCheckGlErrors("objectIdOracle"); !s) return s;

  // Per object: 1 if some fragment lies within its box's depth range, 2 if it only has
  // fragments nearer than that. Judged with the default margins (the projector's), widened
  // kArtifactMargins times, whatever the culler's projection settings: a culler whose
  // margins are too small (or whose boxes do not enclose their geometry in depth) then
  // shows misses, not artifacts; only fragments far nearer than any interpolation of
  // their own geometry count as artifacts.
  constexpr float kArtifactMargins = 16.0f;
  const std::size_t objects = object_boxes.size();
  std::vector<std::uint8_t> state(objects, 0);
  std::vector<float> threshold(objects, 0);
  const float sign = camera.depth.convention == DepthConvention::Reversed ? -1.0f : 1.0f;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const std::uint32_t id = ids[i];
    if (id >= objects || state[id] == 1) continue;
    if (state[id] == 0) {
      const BoxProjection p = projector.project(object_boxes[id]);
      threshold[id] = p.cls == ProjectionClass::Inside ? p.near_key - kArtifactMargins * p.margin
                                                       : -std::numeric_limits<float>::infinity();
    }
    state[id] = sign * depth[i] >= threshold[id] ? 1 : 2;
  }
  OracleFrame out;
  for (ObjectId id = 0; id < objects; ++id) {
    if (state[id] == 1) out.visible.push_back(id);
    if (state[id] == 2) out.artifacts.push_back(id);
  }
  return out;
}

}  // namespace

Result<OracleFrame> tryObjectIdOracle(const Framebuffer& framebuffer, const Camera& camera,
                                      const std::vector<Aabb>& object_boxes,
                                      const std::function<void()>& draw_ids) {
  if (Status s = checkFramebuffer(framebuffer, camera); !s) return s;  // first, as ever
  const Result<Projector> made = Projector::create(camera);
  if (!made) return made.status();
  return idPass(framebuffer, made.value(), object_boxes, draw_ids);
}

Result<OracleFrame> tryObjectIdOracle(const Framebuffer& framebuffer, const Projector& projector,
                                      const std::vector<Aabb>& object_boxes,
                                      const std::function<void()>& draw_ids) {
  if (Status s = checkFramebuffer(framebuffer, projector.camera()); !s) return s;
  return idPass(framebuffer, projector, object_boxes, draw_ids);
}

}  // namespace logrid::gl
