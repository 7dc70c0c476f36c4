// A small OpenGL 4.5 core renderer for culling experiments: one vertex buffer, one
// index buffer, a draw call per object or a few per batch of objects (drawBatch), with a
// flat colour per object (or colours per vertex), Lambert-shaded
// with normals derived per pixel (no normals stored), and an object-ID pass that writes each
// object's id into an R32UI attachment.
//
// Precision: positions are local to the scene; the renderer draws camera-relative. It
// takes a logrid::Camera whose view_projection maps *local* positions to clip space and
// whose render_origin is the eye in local coordinates, and computes in double
//   u_vp = view_projection * translation(render_origin),  u_offset = -render_origin
// so the shader's float math sees only small numbers: gl_Position = u_vp * (p + u_offset).
// The culler gets the same camera, so its margins model exactly this transform.
//
// Moving objects: an object may have a rigid transform (setTransform): its vertices p
// are drawn at rotation * p + translation (local scene coordinates), computed in the
// shader as u_rotation * p + u_offset with u_offset = translation - render_origin taken
// in double and rounded once to float; objects without one get the identity, whose
// product is exact, so they are drawn exactly as without transforms. The box an
// application gives the culler for a transformed object must hold the transformed
// geometry with the float rounding of the rotation (a few ulps of the object's own size;
// samples/scene/motion.cpp pads by it); the remaining rounding, relative to the distance
// from the render origin, is what projection.hpp's render-error margin covers.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/error.hpp"
#include "logrid/types.hpp"

namespace logrid::gl {

struct RenderMesh {
  struct Draw {
    std::uint32_t first_index = 0;
    std::uint32_t index_count = 0;
    std::int32_t base_vertex = 0;
    std::uint32_t color = 0xFFFFFFFFu;  // RGBA8: r | g << 8 | b << 16 | a << 24
  };
  std::vector<float> positions;          // xyz per vertex
  std::vector<std::uint32_t> colors;     // optional RGBA8 per vertex (else Draw::color)
  std::vector<std::uint16_t> indices16;  // used when non-empty (every draw < 65536 vertices)
  std::vector<std::uint32_t> indices32;  // otherwise
  std::vector<Draw> draws;               // one per object, indexed by ObjectId

  std::size_t triangleCount() const {
    return (indices16.empty() ? indices32.size() : indices16.size()) / 3;
  }
  std::size_t memoryBytes() const;
};

// A rigid transform of one object: rotation (3x3, column-major) about the local origin,
// then translation, in the scene's local coordinates.
struct ObjectTransform {
  float rotation[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  DVec3 translation;
};

enum class Pass : std::uint8_t {
  Shaded,     // colour + depth
  ObjectIds,  // object id into colour attachment 1 + depth (Framebuffer::selectIdPass)
  DepthOnly,  // depth only
};

class MeshRenderer {
 public:
  // Uploads the mesh (requires a current GL 4.5 context). The result form
  // (logrid/error.hpp): the renderer, or ErrorCode::InvalidArgument when draws reference
  // indices or vertices outside the arrays or the colours do not match the vertices,
  // ErrorCode::Runtime when GL runs out of memory or fails.
  static Result<std::unique_ptr<MeshRenderer>> create(const RenderMesh& mesh);
  // The throwing form: throws logrid::Error where create() fails.
  explicit MeshRenderer(const RenderMesh& mesh);
  ~MeshRenderer();
  MeshRenderer(const MeshRenderer&) = delete;
  MeshRenderer& operator=(const MeshRenderer&) = delete;

  std::size_t objectCount() const { return draws_.size(); }
  std::uint32_t triangles(ObjectId id) const { return draws_[id].index_count / 3; }
  std::uint64_t gpuBytes() const { return gpu_bytes_; }

  // Back faces culled (counter-clockwise triangles face the viewer) from the next
  // begin() on, in every pass, and face culling off again at end(). Off (the default):
  // the renderer leaves face culling as the application set it.
  void setCullBackFaces(bool cull) { cull_back_faces_ = cull; }
  // Binds program, vertex array and per-frame uniforms for a pass.
  void begin(Pass pass, const Camera& camera);
  void draw(ObjectId id);
  // Draws `count` objects (a batch of the culler's) in as few calls as it can: those
  // without a transform in one glMultiDrawElementsBaseVertex per colour (one in all
  // where the mesh has colours per vertex, and in the depth-only pass), ranges that
  // follow each other in the index buffer over the same vertices (the clusters of an
  // object) merged into one; transformed objects likewise, one call per run of ids that
  // follow each other with the same transform and colour (the clusters of a moving
  // object); in the object-ID pass every object one call (its id is a uniform). The
  // objects are drawn in another order.
  void drawBatch(const ObjectId* ids, std::size_t count);
  void end();
  // Draw calls made so far (a frame's: the difference across it).
  std::uint64_t drawCalls() const { return draw_calls_; }

  // Gives object `id` a transform (until cleared), or takes it away. Takes effect at the
  // next draw; cheap (one uniform update per draw of a transformed object). In both
  // forms: ErrorCode::InvalidArgument for an unknown object or a non-finite transform.
  Status trySetTransform(ObjectId id, const ObjectTransform& transform);
  void setTransform(ObjectId id, const ObjectTransform& transform);
  void clearTransform(ObjectId id);
  bool hasTransform(ObjectId id) const { return id < moving_.size() && moving_[id]; }

 private:
  struct Empty {};
  explicit MeshRenderer(Empty);  // nothing uploaded: upload() does
  Status upload(const RenderMesh& mesh);
  void bindIdentity();
  void bindTransformOf(ObjectId id);  // its transform, or the identity
  struct Programs;
  std::unique_ptr<Programs> programs_;
  std::vector<RenderMesh::Draw> draws_;
  std::uint32_t vao_ = 0;
  std::uint32_t vertex_buffer_ = 0;
  std::uint32_t index_buffer_ = 0;
  std::uint32_t color_buffer_ = 0;
  bool vertex_colors_ = false;
  std::uint32_t index_type_ = 0;
  std::size_t index_bytes_ = 0;
  std::uint64_t gpu_bytes_ = 0;
  Pass pass_ = Pass::Shaded;
  std::int32_t id_location_ = -1;
  std::int32_t rotation_location_ = -1;
  std::int32_t offset_location_ = -1;
  DVec3 origin_;                // this pass's render origin, rounded to float
  bool identity_bound_ = true;  // the uniforms hold the identity transform
  std::vector<ObjectTransform> transforms_;
  std::vector<std::uint8_t> moving_;
  std::uint64_t draw_calls_ = 0;
  bool cull_back_faces_ = false;
  // drawBatch()'s scratch: the objects it draws together (without and with a
  // transform), and the ranges of one call.
  std::vector<ObjectId> together_;
  std::vector<ObjectId> moved_;
  std::vector<std::int32_t> counts_;
  std::vector<const void*> offsets_;
  std::vector<std::int32_t> base_vertices_;
};

#if LOGRID_HAS_EXCEPTIONS
inline MeshRenderer::MeshRenderer(const RenderMesh& mesh) : MeshRenderer(Empty{}) {
  logrid::orThrow(upload(mesh));
}
inline void MeshRenderer::setTransform(ObjectId id, const ObjectTransform& transform) {
  logrid::orThrow(trySetTransform(id, transform));
}
#endif

}  // namespace logrid::gl
