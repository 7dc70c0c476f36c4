// The object-ID oracle (logrid/gl/object_id_oracle.hpp) on a known frame: a wall, a box
// in front of it, one hidden behind it, one behind the camera, and a triangle whose
// declared box lies far behind its geometry (so its fragments are nearer than any
// interpolation of its box allows: an artifact), in both depth conventions.
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <string>

#include "gl_test_context.hpp"
#include "logrid/cpu/software_rasterizer.hpp"
#include "logrid/error.hpp"
#include "logrid/gl/context.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/gl/mesh_renderer.hpp"
#include "logrid/gl/object_id_oracle.hpp"
#include "logrid/projection.hpp"

namespace logrid {
namespace {

enum : ObjectId { kWall, kFront, kHidden, kBehindEye, kArtifact, kObjects };

struct KnownFrame {
  gl::RenderMesh mesh;
  std::vector<Aabb> boxes;  // per object, as the culler's hierarchy would declare them
};

// The camera at (0, 0, 10) looks down -z: the wall at z = 0 fills the view.
KnownFrame knownFrame() {
  KnownFrame f;
  std::vector<std::uint32_t> indices;
  auto add = [&](const Aabb& geometry, const Aabb& declared) {
    gl::RenderMesh::Draw d;
    d.first_index = std::uint32_t(indices.size());
    cpu::appendBox(geometry, f.mesh.positions, indices);
    d.index_count = std::uint32_t(indices.size()) - d.first_index;
    f.mesh.draws.push_back(d);
    f.boxes.push_back(declared);
  };
  const Aabb wall{{-50, -50, 0}, {50, 50, 0}};
  const Aabb front{{-1, -1, 2}, {1, 1, 3}};
  const Aabb hidden{{-1, -1, -3}, {1, 1, -2}};
  const Aabb behind_eye{{-1, -1, 12}, {1, 1, 13}};
  const Aabb near_quad{{2, 2, 5}, {3, 3, 5}};
  const Aabb far_away{{2, 2, -40}, {3, 3, -39}};  // declared far behind its geometry
  add(wall, wall);
  add(front, front);
  add(hidden, hidden);
  add(behind_eye, behind_eye);
  add(near_quad, far_away);
  f.mesh.indices32 = indices;
  return f;
}

Camera knownCamera(DepthConvention convention) {
  Camera cam;
  cam.width = 64;
  cam.height = 48;
  cam.depth = {convention,
               convention == DepthConvention::Reversed ? ClipDepthRange::ZeroToOne
                                                       : ClipDepthRange::NegativeOneToOne,
               DepthFormat::D32F};
  cam.view_projection = multiply(perspective(1.2, 64.0 / 48.0, 0.5, 100, cam.depth),
                                 lookAt({0, 0, 10}, {0, 0, 0}, {0, 1, 0}));
  return cam;
}

class ObjectIdOracleTest : public testing::TestWithParam<DepthConvention> {};

TEST_P(ObjectIdOracleTest, FindsTheVisibleObjectsAndTheArtifacts) {
  LOGRID_REQUIRE_GL();
  const KnownFrame f = knownFrame();
  const Camera cam = knownCamera(GetParam());
  gl::MeshRenderer renderer(f.mesh);
  gl::Framebuffer fb({cam.width, cam.height, cam.depth, true});
  // The colour of the frame is left alone.
  const float grey[4] = {0.5f, 0.5f, 0.5f, 1.0f};
  fb.bind();
  fb.clear(grey);
  const std::vector<std::uint8_t> before = fb.readColor();

  int calls = 0;
  const gl::OracleFrame oracle = gl::objectIdOracle(fb, cam, f.boxes, [&] {
    ++calls;
    renderer.begin(gl::Pass::ObjectIds, cam);
    for (ObjectId id = 0; id < kObjects; ++id) renderer.draw(id);
    renderer.end();
  });
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(oracle.visible, (std::vector<ObjectId>{kWall, kFront}));
  EXPECT_EQ(oracle.artifacts, (std::vector<ObjectId>{kArtifact}));
  EXPECT_EQ(fb.readColor(), before);

  // What a culler that left out the box in front would be told.
  EXPECT_EQ(oracle.missedBy({kWall, kHidden, kWall}), (std::vector<ObjectId>{kFront}));
  EXPECT_TRUE(oracle.missedBy({kFront, kWall}).empty());

  // The same pass with the artifact's true box: then it is simply visible.
  std::vector<Aabb> true_boxes = f.boxes;
  true_boxes[kArtifact] = {{2, 2, 5}, {3, 3, 5}};
  const gl::OracleFrame exact = gl::objectIdOracle(fb, cam, true_boxes, [&] {
    renderer.begin(gl::Pass::ObjectIds, cam);
    for (ObjectId id = 0; id < kObjects; ++id) renderer.draw(id);
    renderer.end();
  });
  EXPECT_EQ(exact.visible, (std::vector<ObjectId>{kWall, kFront, kArtifact}));
  EXPECT_TRUE(exact.artifacts.empty());
}

// A depth source under GlStatePolicy::ApplicationManaged leaves its draws' state set (a
// multisample resolve: the scissor test on around its last rectangle, colour writes off).
// The oracle's clear and ID draws must not depend on it: before Framebuffer::bind() set
// both, the IDs of an earlier pass survived the clear and the draws were scissored.
TEST_P(ObjectIdOracleTest, IgnoresTheScissorAndColourMasksASourceLeft) {
  LOGRID_REQUIRE_GL();
  const KnownFrame f = knownFrame();
  const Camera cam = knownCamera(GetParam());
  gl::MeshRenderer renderer(f.mesh);
  gl::Framebuffer fb({cam.width, cam.height, cam.depth, true});
  auto leaveSourceState = [] {
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, 1, 1);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  };
  auto drawAll = [&] {
    renderer.begin(gl::Pass::ObjectIds, cam);
    for (ObjectId id = 0; id < kObjects; ++id) renderer.draw(id);
    renderer.end();
  };
  const gl::OracleFrame full = gl::objectIdOracle(fb, cam, f.boxes, drawAll);
  EXPECT_EQ(full.visible, (std::vector<ObjectId>{kWall, kFront}));
  // The form for a frame whose projector the application holds answers alike.
  const gl::OracleFrame projected = gl::objectIdOracle(fb, Projector(cam), f.boxes, drawAll);
  EXPECT_EQ(projected.visible, full.visible) << "objectIdOracle's Projector form";
  EXPECT_EQ(projected.artifacts, full.artifacts) << "objectIdOracle's Projector form";
  leaveSourceState();
  const gl::OracleFrame empty = gl::objectIdOracle(fb, cam, f.boxes, [] {});
  EXPECT_TRUE(empty.visible.empty()) << "the last pass's IDs survived the clear";
  leaveSourceState();
  const gl::OracleFrame again = gl::objectIdOracle(fb, cam, f.boxes, drawAll);
  EXPECT_EQ(again.visible, full.visible) << "the ID draws were scissored";
  EXPECT_EQ(again.artifacts, full.artifacts);
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  gl::checkGlErrors("IgnoresTheScissorAndColourMasksASourceLeft");
}

TEST_P(ObjectIdOracleTest, RefusesAFramebufferThatCannotHoldTheFrame) {
  LOGRID_REQUIRE_GL();
  const KnownFrame f = knownFrame();
  const Camera cam = knownCamera(GetParam());
  const Projector projector(cam);
  auto expectInvalid = [&](const gl::FramebufferDesc& desc, const char* needle) {
    gl::Framebuffer fb(desc);
    auto drawNothing = [] { FAIL() << "drew into a wrong framebuffer"; };
    try {
      gl::objectIdOracle(fb, cam, f.boxes, drawNothing);
      FAIL() << "accepted: " << needle;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
    // The form for a frame's projector checks alike.
    const Status s = gl::tryObjectIdOracle(fb, projector, f.boxes, drawNothing).status();
    EXPECT_FALSE(s.ok()) << "the Projector form accepted: " << needle;
    EXPECT_EQ(s.code(), ErrorCode::InvalidArgument);
    EXPECT_NE(s.message().find(needle), std::string::npos) << s.message();
  };
  expectInvalid({cam.width, cam.height, cam.depth, false}, "no object-ID attachment");
  expectInvalid({cam.width + 1, cam.height, cam.depth, true}, "65x48");
  DepthSetup d16 = cam.depth;
  d16.format = DepthFormat::D16;
  expectInvalid({cam.width, cam.height, d16, true}, "format 16");
}

INSTANTIATE_TEST_SUITE_P(Conventions, ObjectIdOracleTest,
                         testing::Values(DepthConvention::Standard, DepthConvention::Reversed),
                         [](const testing::TestParamInfo<DepthConvention>& param) {
                           return std::string(toString(param.param));
                         });

}  // namespace
}  // namespace logrid
