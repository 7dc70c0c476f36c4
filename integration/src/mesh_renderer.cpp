#include "logrid/gl/mesh_renderer.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>
#include <utility>

#include "logrid/gl/context.hpp"
#include "logrid/zread/program.hpp"

namespace logrid::gl {

std::size_t RenderMesh::memoryBytes() const {
  return positions.capacity() * sizeof(float) + colors.capacity() * 4 + indices16.capacity() * 2 +
         indices32.capacity() * 4 + draws.capacity() * sizeof(Draw);
}

namespace {

// `invariant` keeps the shaded, ID and depth passes at identical depths, which the
// object-ID oracle relies on.
constexpr const char* kVertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_color;  // per vertex, or the draw's colour (generic value)
uniform mat4 u_vp;
uniform mat3 u_rotation;  // identity for objects without a transform: exact
uniform vec3 u_offset;
out vec3 v_relative;
out vec4 v_color;
invariant gl_Position;
void main() {
  v_relative = u_rotation * a_position + u_offset;
  v_color = a_color;
  gl_Position = u_vp * vec4(v_relative, 1.0);
}
)";

// Flat shading from screen-space derivatives of the camera-relative position: the
// face normal, for free, without a normal attribute.
constexpr const char* kShaded = R"(#version 450 core
in vec3 v_relative;
in vec4 v_color;
layout(location = 0) out vec4 o_color;
void main() {
  vec3 n = normalize(cross(dFdx(v_relative), dFdy(v_relative)));
  const vec3 sun = normalize(vec3(0.45, 0.8, 0.35));
  float light = 0.35 + 0.65 * abs(dot(n, sun));
  o_color = vec4(v_color.rgb * light, 1.0);
}
)";

constexpr const char* kIds = R"(#version 450 core
uniform uint u_object;
layout(location = 1) out uint o_id;
void main() { o_id = u_object; }
)";

// x rounded to the nearest float (ties to even, as a conversion rounds), in double
// arithmetic. Not double(float(x)): GCC 12.2 at -O2 folds that round trip away when it
// vectorises two of them side by side (the SLP vectoriser), leaving x unrounded.
double roundToFloat(double x) {
  if (x == 0 || !std::isfinite(x)) return x;
  int exponent = 0;
  std::frexp(x, &exponent);                             // |x| = m 2^exponent, 0.5 <= m < 1
  const double scale = std::ldexp(1.0, 24 - exponent);  // 24 significant bits, as a float has
  return std::nearbyint(x * scale) / scale;             // exact scaling by powers of two
}

constexpr const char* kDepthOnly = R"(#version 450 core
void main() {}
)";

}  // namespace

struct MeshRenderer::Programs {
  std::unique_ptr<zread::Program> shaded, ids, depth;
};

MeshRenderer::MeshRenderer(Empty) {}

Result<std::unique_ptr<MeshRenderer>> MeshRenderer::create(const RenderMesh& mesh) {
  std::unique_ptr<MeshRenderer> renderer(new MeshRenderer(Empty{}));
  if (Status s = renderer->upload(mesh); !s) return s;
  return Result<std::unique_ptr<MeshRenderer>>(std::move(renderer));
}

Status MeshRenderer::upload(const RenderMesh& mesh) {
  const bool small = !mesh.indices16.empty();
  const std::size_t index_count = small ? mesh.indices16.size() : mesh.indices32.size();
  const std::size_t vertices = mesh.positions.size() / 3;
  for (std::size_t i = 0; i < mesh.draws.size(); ++i) {
    const RenderMesh::Draw& d = mesh.draws[i];
    if (std::uint64_t(d.first_index) + d.index_count > index_count || d.base_vertex < 0 ||
        std::uint64_t(d.base_vertex) > vertices) {
      std::ostringstream out;
      out << "MeshRenderer: draw " << i << " (indices " << d.first_index << "+" << d.index_count
          << ", base vertex " << d.base_vertex << ") lies outside the mesh (" << index_count
          << " indices, " << vertices << " vertices)";
      return Status(ErrorCode::InvalidArgument, out.str());
    }
  }
  if (!mesh.colors.empty() && mesh.colors.size() != vertices) {
    return Status(ErrorCode::InvalidArgument,
                  "MeshRenderer: " + std::to_string(mesh.colors.size()) + " colours for " +
                      std::to_string(vertices) + " vertices");
  }
  programs_ = std::make_unique<Programs>();
  for (auto [program, name, fragment] : {std::tuple{&programs_->shaded, "mesh shaded", kShaded},
                                         std::tuple{&programs_->ids, "mesh ids", kIds},
                                         std::tuple{&programs_->depth, "mesh depth", kDepthOnly}}) {
    Result<std::unique_ptr<zread::Program>> made = zread::Program::create(name, kVertex, fragment);
    if (!made) return made.status();
    *program = std::move(made).value();
  }
  draws_ = mesh.draws;
  if (Status s = tryCheckGlErrors("MeshRenderer: before upload"); !s) return s;
  index_type_ = small ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
  index_bytes_ = small ? 2 : 4;
  const std::size_t vertex_bytes = mesh.positions.size() * sizeof(float);
  const std::size_t color_bytes = mesh.colors.size() * 4;
  const std::size_t index_bytes = index_count * index_bytes_;
  glCreateBuffers(1, &vertex_buffer_);
  glNamedBufferStorage(vertex_buffer_, GLsizeiptr(std::max<std::size_t>(vertex_bytes, 4)),
                       mesh.positions.empty() ? nullptr : mesh.positions.data(), 0);
  glCreateBuffers(1, &index_buffer_);
  const void* index_data = small ? static_cast<const void*>(mesh.indices16.data())
                                 : static_cast<const void*>(mesh.indices32.data());
  glNamedBufferStorage(index_buffer_, GLsizeiptr(std::max<std::size_t>(index_bytes, 4)),
                       index_count ? index_data : nullptr, 0);
  if (glGetError() == GL_OUT_OF_MEMORY) {
    return Status(ErrorCode::Runtime, "MeshRenderer: out of GL memory uploading " +
                                          std::to_string(vertex_bytes + index_bytes) + " bytes");
  }
  glCreateVertexArrays(1, &vao_);
  glVertexArrayVertexBuffer(vao_, 0, vertex_buffer_, 0, 3 * sizeof(float));
  glVertexArrayElementBuffer(vao_, index_buffer_);
  glEnableVertexArrayAttrib(vao_, 0);
  glVertexArrayAttribFormat(vao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao_, 0, 0);
  vertex_colors_ = !mesh.colors.empty();
  if (vertex_colors_) {
    glCreateBuffers(1, &color_buffer_);
    glNamedBufferStorage(color_buffer_, GLsizeiptr(color_bytes), mesh.colors.data(), 0);
    glVertexArrayVertexBuffer(vao_, 1, color_buffer_, 0, 4);
    glEnableVertexArrayAttrib(vao_, 1);
    glVertexArrayAttribFormat(vao_, 1, 4, GL_UNSIGNED_BYTE, GL_TRUE, 0);
    glVertexArrayAttribBinding(vao_, 1, 1);
  }
  if (glGetError() == GL_OUT_OF_MEMORY) {
    return Status(ErrorCode::Runtime, "MeshRenderer: out of GL memory uploading " +
                                          std::to_string(color_bytes) + " bytes of colours");
  }
  gpu_bytes_ = vertex_bytes + index_bytes + color_bytes;
  return tryCheckGlErrors("MeshRenderer: upload");
}

MeshRenderer::~MeshRenderer() {
  // A renderer whose upload() refused the mesh made no GL object: no GL call then.
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (vertex_buffer_) glDeleteBuffers(1, &vertex_buffer_);
  if (index_buffer_) glDeleteBuffers(1, &index_buffer_);
  if (color_buffer_) glDeleteBuffers(1, &color_buffer_);
}

void MeshRenderer::begin(Pass pass, const Camera& camera) {
  pass_ = pass;
  const zread::Program& program = pass == Pass::Shaded      ? *programs_->shaded
                                  : pass == Pass::ObjectIds ? *programs_->ids
                                                            : *programs_->depth;
  program.use();
  // The shader subtracts the origin in float, i.e. the origin rounded to float: far from
  // zero that is up to half a float ulp away from render_origin (4 units at 1e8).
  // Translate the matrix by the same rounded origin, so that the two cancel exactly and
  // the drawn geometry does not shift against what the culler projects.
  const DVec3 origin{roundToFloat(camera.render_origin.x), roundToFloat(camera.render_origin.y),
                     roundToFloat(camera.render_origin.z)};
  const Mat4d vp = multiply(camera.view_projection, translation(origin));
  float m[16];
  for (int i = 0; i < 16; ++i) m[i] = static_cast<float>(vp.m[i]);
  glUniformMatrix4fv(program.uniform("u_vp"), 1, GL_FALSE, m);
  origin_ = origin;
  rotation_location_ = program.uniform("u_rotation");
  offset_location_ = program.uniform("u_offset");
  bindIdentity();
  id_location_ = pass == Pass::ObjectIds ? program.uniform("u_object") : -1;
  const GLboolean color_writes = pass == Pass::DepthOnly ? GL_FALSE : GL_TRUE;
  glColorMask(color_writes, color_writes, color_writes, color_writes);
  if (cull_back_faces_) {
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
  }
  glBindVertexArray(vao_);
}

namespace {

// Attribute 1 has no array: the shader reads this generic value.
void setDrawColor(std::uint32_t c) {
  glVertexAttrib4Nub(1, GLubyte(c & 0xFF), GLubyte((c >> 8) & 0xFF), GLubyte((c >> 16) & 0xFF),
                     GLubyte(c >> 24));
}

}  // namespace

void MeshRenderer::draw(ObjectId id) {
  const RenderMesh::Draw& d = draws_[id];
  if (pass_ == Pass::Shaded && !vertex_colors_) {
    setDrawColor(d.color);
  } else if (pass_ == Pass::ObjectIds) {
    glUniform1ui(id_location_, id);
  }
  bindTransformOf(id);
  glDrawElementsBaseVertex(GL_TRIANGLES, GLsizei(d.index_count), index_type_,
                           reinterpret_cast<const void*>(std::size_t(d.first_index) * index_bytes_),
                           d.base_vertex);
  ++draw_calls_;
}

void MeshRenderer::bindTransformOf(ObjectId id) {
  if (id < moving_.size() && moving_[id]) {
    const ObjectTransform& t = transforms_[id];
    glUniformMatrix3fv(rotation_location_, 1, GL_FALSE, t.rotation);
    // The translation relative to the render origin, in double, rounded once.
    glUniform3f(offset_location_, static_cast<float>(t.translation.x - origin_.x),
                static_cast<float>(t.translation.y - origin_.y),
                static_cast<float>(t.translation.z - origin_.z));
    identity_bound_ = false;
  } else if (!identity_bound_) {
    bindIdentity();
  }
}

namespace {

bool sameTransform(const ObjectTransform& a, const ObjectTransform& b) {
  return std::equal(a.rotation, a.rotation + 9, b.rotation) && a.translation.x == b.translation.x &&
         a.translation.y == b.translation.y && a.translation.z == b.translation.z;
}

}  // namespace

void MeshRenderer::drawBatch(const ObjectId* ids, std::size_t count) {
  if (pass_ == Pass::ObjectIds) {  // every object its own id: one call each
    for (std::size_t i = 0; i < count; ++i) draw(ids[i]);
    return;
  }
  together_.clear();
  moved_.clear();
  for (std::size_t i = 0; i < count; ++i) {
    const ObjectId id = ids[i];
    (id < moving_.size() && moving_[id] ? moved_ : together_).push_back(id);
  }
  const bool by_color = pass_ == Pass::Shaded && !vertex_colors_;
  // Without a transform: by colour where it matters, then by place in the index buffer,
  // so that an object's clusters drawn together become one range.
  std::sort(together_.begin(), together_.end(), [&](ObjectId a, ObjectId b) {
    const RenderMesh::Draw &da = draws_[a], &db = draws_[b];
    if (by_color && da.color != db.color) return da.color < db.color;
    return da.first_index < db.first_index;
  });
  // Transformed: by id, so that the parts of one moving object (ids that follow each
  // other, with one transform: a mover's clusters) are drawn together.
  std::sort(moved_.begin(), moved_.end());
  auto drawRuns = [&](const std::vector<ObjectId>& objects, auto same_call) {
    for (std::size_t run = 0; run < objects.size();) {
      const ObjectId first = objects[run];
      counts_.clear(), offsets_.clear(), base_vertices_.clear();
      std::uint32_t next_index = 0;  // where the last range ends
      std::size_t i = run;
      for (; i < objects.size() && (i == run || same_call(first, objects[i])); ++i) {
        const RenderMesh::Draw& d = draws_[objects[i]];
        if (!counts_.empty() && d.first_index == next_index &&
            d.base_vertex == base_vertices_.back()) {
          counts_.back() += GLsizei(d.index_count);
        } else {
          counts_.push_back(GLsizei(d.index_count));
          offsets_.push_back(
              reinterpret_cast<const void*>(std::size_t(d.first_index) * index_bytes_));
          base_vertices_.push_back(d.base_vertex);
        }
        next_index = d.first_index + d.index_count;
      }
      if (by_color) setDrawColor(draws_[first].color);
      bindTransformOf(first);
      glMultiDrawElementsBaseVertex(GL_TRIANGLES, counts_.data(), index_type_, offsets_.data(),
                                    GLsizei(counts_.size()), base_vertices_.data());
      ++draw_calls_;
      run = i;
    }
  };
  drawRuns(together_,
           [&](ObjectId a, ObjectId b) { return !by_color || draws_[a].color == draws_[b].color; });
  drawRuns(moved_, [&](ObjectId a, ObjectId b) {
    return (!by_color || draws_[a].color == draws_[b].color) &&
           sameTransform(transforms_[a], transforms_[b]);
  });
}

void MeshRenderer::bindIdentity() {
  static constexpr float kIdentity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  glUniformMatrix3fv(rotation_location_, 1, GL_FALSE, kIdentity);
  // Exact: each value is a float already.
  glUniform3f(offset_location_, static_cast<float>(-origin_.x), static_cast<float>(-origin_.y),
              static_cast<float>(-origin_.z));
  identity_bound_ = true;
}

Status MeshRenderer::trySetTransform(ObjectId id, const ObjectTransform& transform) {
  if (id >= draws_.size()) {
    return Status(ErrorCode::InvalidArgument, "MeshRenderer::setTransform: object " +
                                                  std::to_string(id) + " does not exist (" +
                                                  std::to_string(draws_.size()) + " objects)");
  }
  for (float v : transform.rotation) {
    if (!std::isfinite(v)) {
      return Status(ErrorCode::InvalidArgument, "MeshRenderer::setTransform: object " +
                                                    std::to_string(id) +
                                                    " has a non-finite rotation element");
    }
  }
  if (!std::isfinite(transform.translation.x) || !std::isfinite(transform.translation.y) ||
      !std::isfinite(transform.translation.z)) {
    return Status(ErrorCode::InvalidArgument, "MeshRenderer::setTransform: object " +
                                                  std::to_string(id) +
                                                  " has a non-finite translation");
  }
  if (transforms_.size() < draws_.size()) {
    transforms_.resize(draws_.size());
    moving_.resize(draws_.size(), 0);
  }
  transforms_[id] = transform;
  moving_[id] = 1;
  return {};
}

void MeshRenderer::clearTransform(ObjectId id) {
  if (id < moving_.size()) moving_[id] = 0;
}

void MeshRenderer::end() {
  glBindVertexArray(0);
  if (cull_back_faces_) glDisable(GL_CULL_FACE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

}  // namespace logrid::gl
