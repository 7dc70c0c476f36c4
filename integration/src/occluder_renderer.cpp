#include "logrid/gl/occluder_renderer.hpp"

#include <epoxy/gl.h>

#include <utility>

#include "logrid/gl/context.hpp"
#include "logrid/zread/gl_state.hpp"
#include "logrid/zread/program.hpp"

namespace logrid::gl {
namespace {

constexpr const char* kVertex = R"(#version 450 core
layout(location = 0) in vec3 a_ndc;
void main() { gl_Position = vec4(a_ndc, 1.0); }
)";

constexpr const char* kFragment = R"(#version 450 core
void main() {}
)";

}  // namespace

struct OccluderRenderer::Program {
  std::unique_ptr<zread::Program> program;
};

OccluderRenderer::OccluderRenderer(Empty) {}

Result<std::unique_ptr<OccluderRenderer>> OccluderRenderer::create() {
  std::unique_ptr<OccluderRenderer> renderer(new OccluderRenderer(Empty{}));
  if (Status s = renderer->make(); !s) return s;
  return Result<std::unique_ptr<OccluderRenderer>>(std::move(renderer));
}

Status OccluderRenderer::make() {
  Result<std::unique_ptr<zread::Program>> program =
      zread::Program::create("ddo occluders", kVertex, kFragment);
  if (!program) return program.status();
  program_ = std::make_unique<Program>(Program{std::move(program).value()});
  guard_ = std::make_unique<zread::GlStateGuard>();
  glCreateVertexArrays(1, &vao_);
  glCreateBuffers(1, &buffer_);
  glEnableVertexArrayAttrib(vao_, 0);
  glVertexArrayAttribFormat(vao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao_, 0, 0);
  return tryCheckGlErrors("OccluderRenderer");
}

OccluderRenderer::~OccluderRenderer() {
  if (buffer_) glDeleteBuffers(1, &buffer_);
  if (vao_) glDeleteVertexArrays(1, &vao_);
}

Status OccluderRenderer::tryDraw(const std::vector<ddo::Occluder>& occluders, const Camera& camera,
                                 std::uint32_t framebuffer) {
  if (occluders.empty()) return {};
  vertices_.clear();
  static const int kCorners[6] = {0, 1, 2, 0, 2, 3};
  for (const ddo::Occluder& o : occluders) {
    for (int c : kCorners) {
      for (int k = 0; k < 3; ++k) vertices_.push_back(float(o.ndc[c][k]));
    }
  }
  zread::GlStateGuard::Scope scope(*guard_, "OccluderRenderer::draw");
  // Named-object calls only until prepareDraw(): no binding of the application changes.
  if (vertices_.size() > capacity_) {
    capacity_ = vertices_.size() * 2;
    glNamedBufferData(buffer_, GLsizeiptr(capacity_ * sizeof(float)), nullptr, GL_STREAM_DRAW);
    glVertexArrayVertexBuffer(vao_, 0, buffer_, 0, 3 * sizeof(float));
  }
  glNamedBufferSubData(buffer_, 0, GLsizeiptr(vertices_.size() * sizeof(float)), vertices_.data());
  const bool reversed = camera.depth.convention == DepthConvention::Reversed;
  if (!scope.prepareDraw(framebuffer, std::int32_t(camera.width), std::int32_t(camera.height),
                         reversed ? GL_GREATER : GL_LESS, true)) {
    return guard_->takeError();
  }
  scope.clipControl(GL_LOWER_LEFT, camera.depth.clip_range == ClipDepthRange::ZeroToOne
                                       ? GL_ZERO_TO_ONE
                                       : GL_NEGATIVE_ONE_TO_ONE);
  // The guard leaves the scissor test on over the whole framebuffer: nothing is cut.
  program_->program->use();
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, GLsizei(vertices_.size() / 3));
  if (!scope.check("OccluderRenderer: glDrawArrays")) return guard_->takeError();
  return {};
}

}  // namespace logrid::gl
