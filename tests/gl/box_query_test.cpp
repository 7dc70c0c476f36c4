// zread::BoxQuerySource on real GL: a box query (the faces of Projector::queryBox's box)
// shows samples wherever the geometry inside the box would, in every depth format and
// convention, including the hardest case, geometry that is the box itself; the answers
// do not depend on the GL state the application left, and that state is restored item by
// item; the calibration of nohc's hardware parameters measures valid times and restores
// the application's program unless the application deleted it.
#include <epoxy/gl.h>
#include <gtest/gtest.h>
#include <limits>

#include <random>

#include "gl_test_context.hpp"
#include "logrid/cpu/software_rasterizer.hpp"
#include "logrid/error.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/gl/mesh_renderer.hpp"
#include "logrid/projection.hpp"
#include "logrid/zread/box_query_source.hpp"
#include "logrid/zread/calibration.hpp"
#include "logrid/zread/program.hpp"

namespace logrid {
namespace {

struct Case {
  DepthFormat format;
  DepthConvention convention;
};

Camera testCamera(const Case& c, std::uint32_t w, std::uint32_t h, double yaw) {
  Camera cam;
  cam.width = w;
  cam.height = h;
  cam.depth = {c.convention,
               c.convention == DepthConvention::Reversed ? ClipDepthRange::ZeroToOne
                                                         : ClipDepthRange::NegativeOneToOne,
               c.format};
  const DVec3 eye{10 * std::sin(yaw), 2, 10 * std::cos(yaw)};
  cam.view_projection = multiply(perspective(1.0, double(w) / h, 0.5, 100, cam.depth),
                                 lookAt(eye, {0, 0, 0}, {0, 1, 0}));
  cam.render_origin = eye;  // the renderer draws camera-relative
  return cam;
}

// Boxes as a mesh, one draw each.
gl::RenderMesh boxMesh(const std::vector<Aabb>& boxes) {
  gl::RenderMesh mesh;
  std::vector<float> positions;
  std::vector<std::uint32_t> indices;
  for (const Aabb& b : boxes) {
    const std::size_t first = indices.size(), base = positions.size() / 3;
    cpu::appendBox(b, positions, indices);
    gl::RenderMesh::Draw d;
    d.first_index = std::uint32_t(first);
    d.index_count = std::uint32_t(indices.size() - first);
    for (std::size_t k = first; k < indices.size(); ++k) indices[k] -= std::uint32_t(base);
    d.base_vertex = std::int32_t(base);
    mesh.draws.push_back(d);
  }
  mesh.positions = positions;
  mesh.indices32 = indices;
  return mesh;
}

class BoxQueryTest : public testing::TestWithParam<Case> {};

TEST_P(BoxQueryTest, ShowsWhereverTheGeometryInsideWouldShow) {
  LOGRID_REQUIRE_GL();
  const Case c = GetParam();
  const std::uint32_t w = 160, h = 100;
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> p(-5, 5), s(0.2f, 2.5f);
  std::vector<Aabb> boxes;
  constexpr int kOccluders = 30, kTests = 120;
  for (int i = 0; i < kOccluders + kTests; ++i) {
    const Vec3 lo{p(rng), p(rng) * 0.4f, p(rng)};
    boxes.push_back({lo, {lo.x + s(rng), lo.y + s(rng), lo.z + s(rng)}});
  }
  // Some test boxes coincide with occluders: their geometry lies on the stored depths.
  for (int i = 0; i < 10; ++i) boxes[kOccluders + i] = boxes[std::size_t(i)];
  gl::MeshRenderer renderer(boxMesh(boxes));
  int shown = 0, hidden_by_box = 0, compared = 0;
  for (double yaw : {0.0, 0.7, 2.1, 4.0}) {
    const Camera cam = testCamera(c, w, h, yaw);
    const Projector projector(cam);
    gl::Framebuffer fb({w, h, cam.depth, false});
    fb.bind();
    const float clear[4] = {0, 0, 0, 1};
    fb.clear(clear);
    renderer.begin(gl::Pass::DepthOnly, cam);
    for (ObjectId id = 0; id < kOccluders; ++id) renderer.draw(id);
    zread::BoxQuerySource queries(fb.handle());
    orThrow(queries.beginQueryFrame(cam));
    GLuint geometry_query = 0;
    glCreateQueries(GL_SAMPLES_PASSED, 1, &geometry_query);
    for (ObjectId id = kOccluders; id < boxes.size(); ++id) {
      const std::optional<QueryBox> q = projector.queryBox(boxes[id]);
      if (!q) continue;  // visible without a query
      // The geometry, as the renderer draws it, against the same buffer, no writes.
      glDepthMask(GL_FALSE);
      glBeginQuery(GL_SAMPLES_PASSED, geometry_query);
      renderer.draw(id);
      glEndQuery(GL_SAMPLES_PASSED);
      glDepthMask(GL_TRUE);
      GLuint geometry = 0;
      glGetQueryObjectuiv(geometry_query, GL_QUERY_RESULT, &geometry);
      const std::uint32_t box = queries.result(queries.issueBoxes(&*q, 1));
      if (geometry > 0) {
        ++shown;
        EXPECT_GT(box, 0u) << "box " << id << " (yaw " << yaw << "): its geometry shows "
                           << geometry << " samples, its query box none";
      } else if (box == 0) {
        ++hidden_by_box;
      }
      ++compared;
    }
    renderer.end();
    orThrow(queries.endQueryFrame());
    glDeleteQueries(1, &geometry_query);
    gl::checkGlErrors("BoxQueryTest");
  }
  EXPECT_GT(shown, 50);
  EXPECT_GT(hidden_by_box, 20) << "the query boxes never found a box hidden";
  std::printf("[ queries ] %d boxes compared: %d shown, %d found hidden by the query\n", compared,
              shown, hidden_by_box);
}

INSTANTIATE_TEST_SUITE_P(AllFormats, BoxQueryTest,
                         testing::Values(Case{DepthFormat::D16, DepthConvention::Standard},
                                         Case{DepthFormat::D24, DepthConvention::Standard},
                                         Case{DepthFormat::D24, DepthConvention::Reversed},
                                         Case{DepthFormat::D32F, DepthConvention::Standard},
                                         Case{DepthFormat::D32F, DepthConvention::Reversed}),
                         [](const testing::TestParamInfo<Case>& p) {
                           return std::string("d") + toString(p.param.format) + "_" +
                                  toString(p.param.convention);
                         });

// The state the application leaves: every item that could change a query's answer set to
// something hostile, and a few bindings of its own.
struct Hostile {
  GLuint framebuffer = 0, program = 0, vertex_array = 0;
  void apply() {
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT_AND_BACK);
    glFrontFace(GL_CW);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_NEVER, 0, 0xFF);
    glDepthFunc(GL_NEVER);
    glDepthMask(GL_TRUE);
    glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, 1, 1);
    glViewport(5, 5, 10, 10);
    glDepthRange(0.2, 0.3);
    glClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_DEPTH_CLAMP);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(100, 100);
    glEnable(GL_CLIP_DISTANCE0);
    glEnable(GL_SAMPLE_MASK);
    glSampleMaski(0, 0);
    glEnable(GL_RASTERIZER_DISCARD);
    glCreateVertexArrays(1, &vertex_array);
    glBindVertexArray(vertex_array);
    program = glCreateProgram();  // unlinked: only its name is bound (no draw follows)
    glCreateFramebuffers(1, &framebuffer);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
  }
  void release() {
    glDisable(GL_RASTERIZER_DISCARD);
    glDeleteProgram(program);
    glDeleteVertexArrays(1, &vertex_array);
    glDeleteFramebuffers(1, &framebuffer);
  }
};

// Every item of Hostile, read back.
std::vector<double> readState() {
  std::vector<double> out;
  auto ints = [&](GLenum name, int n) {
    GLint v[4] = {};
    glGetIntegerv(name, v);
    for (int i = 0; i < n; ++i) out.push_back(v[i]);
  };
  for (GLenum cap :
       {GL_CULL_FACE, GL_STENCIL_TEST, GL_SCISSOR_TEST, GL_DEPTH_CLAMP, GL_POLYGON_OFFSET_FILL,
        GL_CLIP_DISTANCE0, GL_SAMPLE_MASK, GL_RASTERIZER_DISCARD, GL_DEPTH_TEST}) {
    out.push_back(glIsEnabled(cap));
  }
  ints(GL_CULL_FACE_MODE, 1);
  ints(GL_FRONT_FACE, 1);
  ints(GL_POLYGON_MODE, 1);
  ints(GL_STENCIL_FUNC, 1);
  ints(GL_DEPTH_FUNC, 1);
  ints(GL_SCISSOR_BOX, 4);
  ints(GL_VIEWPORT, 4);
  ints(GL_CLIP_ORIGIN, 1);
  ints(GL_CLIP_DEPTH_MODE, 1);
  ints(GL_DRAW_FRAMEBUFFER_BINDING, 1);
  ints(GL_CURRENT_PROGRAM, 1);
  ints(GL_VERTEX_ARRAY_BINDING, 1);
  GLboolean b[4];
  glGetBooleanv(GL_DEPTH_WRITEMASK, b);
  out.push_back(b[0]);
  glGetBooleanv(GL_COLOR_WRITEMASK, b);
  for (int i = 0; i < 4; ++i) out.push_back(b[i]);
  GLfloat f[2];
  glGetFloatv(GL_DEPTH_RANGE, f);
  out.insert(out.end(), {f[0], f[1]});
  glGetFloatv(GL_POLYGON_OFFSET_FACTOR, f);
  out.push_back(f[0]);
  GLint mask = 0;
  glGetIntegeri_v(GL_SAMPLE_MASK_VALUE, 0, &mask);
  out.push_back(mask);
  return out;
}

TEST(BoxQueryState, HostileStateNeitherChangesTheAnswersNorSurvivesThePass) {
  LOGRID_REQUIRE_GL();
  for (const Case c : {Case{DepthFormat::D24, DepthConvention::Standard},
                       Case{DepthFormat::D32F, DepthConvention::Reversed}}) {
    const std::uint32_t w = 64, h = 48;
    const Camera cam = testCamera(c, w, h, 0);
    const Projector projector(cam);
    gl::Framebuffer fb({w, h, cam.depth, false});
    fb.bind();
    const float clear[4] = {0, 0, 0, 1};
    fb.clear(clear);
    // A wall across the middle; one box behind it, one beside it in the open.
    const std::vector<Aabb> boxes = {{{-20, -20, 0}, {0, 20, 0.2f}},
                                     {{-3, -0.5f, -3}, {-2, 0.5f, -2}},
                                     {{2, -0.5f, -3}, {3, 0.5f, -2}}};
    gl::MeshRenderer renderer(boxMesh(boxes));
    renderer.begin(gl::Pass::DepthOnly, cam);
    renderer.draw(0);
    renderer.end();
    const std::vector<float> depth_before = fb.readDepth();
    zread::BoxQuerySource queries(fb.handle());
    orThrow(queries.beginQueryFrame(cam));
    const QueryBox behind = *projector.queryBox(boxes[1]);
    const QueryBox open = *projector.queryBox(boxes[2]);
    const RectQuery open_rect{projector.project(boxes[2]).rect,
                              projector.project(boxes[2]).occlusionThreshold()};
    const std::uint32_t clean_behind = queries.result(queries.issueBoxes(&behind, 1));
    const std::uint32_t clean_open = queries.result(queries.issueBoxes(&open, 1));
    const std::uint32_t clean_rect = queries.result(queries.issueRects(&open_rect, 1));
    ASSERT_EQ(clean_behind, 0u) << "the box behind the wall shows";
    ASSERT_GT(clean_open, 0u) << "the box in the open does not show";
    ASSERT_GT(clean_rect, 0u);

    Hostile hostile;
    hostile.apply();
    const std::vector<double> before = readState();
    const QueryHandle a = queries.issueBoxes(&behind, 1);
    const QueryHandle b = queries.issueBoxes(&open, 1);
    const QueryHandle r = queries.issueRects(&open_rect, 1);
    EXPECT_EQ(readState(), before) << "the query pass left state changed";
    EXPECT_EQ(queries.result(a), clean_behind);
    EXPECT_EQ(queries.result(b), clean_open);
    EXPECT_EQ(queries.result(r), clean_rect);
    orThrow(queries.endQueryFrame());
    hostile.release();
    fb.bind();
    glClipControl(GL_LOWER_LEFT, c.convention == DepthConvention::Reversed
                                     ? GL_ZERO_TO_ONE
                                     : GL_NEGATIVE_ONE_TO_ONE);
    glDisable(GL_CULL_FACE);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_SCISSOR_TEST);
    glDepthRange(0, 1);
    glDisable(GL_DEPTH_CLAMP);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_CLIP_DISTANCE0);
    glDisable(GL_SAMPLE_MASK);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    EXPECT_EQ(fb.readDepth(), depth_before) << "the query pass wrote depth";
    gl::checkGlErrors("HostileState");
  }
}

TEST(BoxQueryErrors, HandlesAndFramesAreChecked) {
  LOGRID_REQUIRE_GL();
  const Camera cam = testCamera({DepthFormat::D24, DepthConvention::Standard}, 16, 16, 0);
  gl::Framebuffer fb({16, 16, cam.depth, false});
  zread::BoxQuerySource queries(fb.handle());
  const QueryBox box{{{-1, -1, -1}, {1, 1, 1}}, 0};
  // A call that fails answers "visible" and keeps its error for takeError().
  const auto expectError = [&](ErrorCode code, const char* part) {
    const Status error = queries.takeError();
    EXPECT_EQ(error.code(), code) << error.message();
    EXPECT_NE(error.message().find(part), std::string::npos) << error.message();
  };
  const QueryHandle early = queries.issueBoxes(&box, 1);  // before beginQueryFrame()
  expectError(ErrorCode::InvalidArgument, "beginQueryFrame() first");
  EXPECT_TRUE(queries.ready(early));
  EXPECT_EQ(queries.result(early), std::numeric_limits<std::uint32_t>::max());
  Camera wrong = cam;
  wrong.depth.format = DepthFormat::D32F;
  EXPECT_EQ(queries.beginQueryFrame(wrong).code(), ErrorCode::InvalidArgument);
  ASSERT_TRUE(queries.beginQueryFrame(cam).ok());
  const QueryHandle h = queries.issueBoxes(&box, 1);
  EXPECT_EQ(queries.endQueryFrame().code(), ErrorCode::Runtime);  // never read
  queries.result(h);
  EXPECT_TRUE(queries.takeError().ok());
  EXPECT_EQ(queries.result(h), std::numeric_limits<std::uint32_t>::max());  // read twice
  expectError(ErrorCode::InvalidArgument, "read already");
  EXPECT_TRUE(queries.ready(12345));
  expectError(ErrorCode::InvalidArgument, "handle 12345");
  EXPECT_TRUE(queries.endQueryFrame().ok());
}

TEST(Calibration, MeasuresValidTimesAndKeepsThemPerRenderer) {
  LOGRID_REQUIRE_GL();
  zread::CalibrationDesc desc;
  desc.size = 64;
  desc.repeats = 1;
  const HardwareParameters p = zread::measureHardwareParameters(desc);
  EXPECT_EQ(validateHardwareParameters(p), "");
  EXPECT_GT(p.query_latency, 0.0);
  EXPECT_GT(p.render_triangle, 0.0);
  const HardwareParameters a = zread::hardwareParameters(), b = zread::hardwareParameters();
  EXPECT_EQ(a.query_setup, b.query_setup) << "measured twice for one renderer";
  EXPECT_EQ(validateHardwareParameters(a), "");
  desc.size = 2;
  EXPECT_THROW(zread::measureHardwareParameters(desc), Error);
  gl::checkGlErrors("Calibration");
}

// A program deleted while current stays current until another is used, and is then gone
// (GL 4.5 §7.3): the calibration, which uses its own, must not rebind the deleted name
// (GL_INVALID_VALUE). The soak met this as a MeshRenderer released after a run, then the
// first nohc run of the process measuring the hardware parameters.
TEST(Calibration, RestoresTheProgramOnlyIfItStillExists) {
  LOGRID_REQUIRE_GL();
  gl::checkGlErrors("before Calibration.RestoresTheProgramOnlyIfItStillExists");
  zread::CalibrationDesc desc;
  desc.size = 16;
  desc.repeats = 1;
  constexpr const char* kVertex = "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n";
  constexpr const char* kFragment = "#version 450 core\nvoid main() {}\n";
  GLint current = 0;
  GLuint deleted = 0;
  {
    zread::Program application("the application's", kVertex, kFragment);
    application.use();
    zread::measureHardwareParameters(desc);
    glGetIntegerv(GL_CURRENT_PROGRAM, &current);
    EXPECT_EQ(GLuint(current), application.handle()) << "a live program is restored";
    deleted = application.handle();
  }  // glDeleteProgram while current
  glGetIntegerv(GL_CURRENT_PROGRAM, &current);
  ASSERT_EQ(GLuint(current), deleted) << "the deleted program is still current (GL 4.5 §7.3)";
  zread::measureHardwareParameters(desc);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR))
      << "measureHardwareParameters rebound program " << deleted << ", deleted and gone";
  glGetIntegerv(GL_CURRENT_PROGRAM, &current);
  EXPECT_EQ(current, 0) << "a deleted program is restored as 0, as GlStateGuard does";
  EXPECT_NO_THROW(gl::checkGlErrors("Calibration.RestoresTheProgramOnlyIfItStillExists"));
}

}  // namespace
}  // namespace logrid
