// logrid/glm_camera.hpp: a camera from an application's GLM matrices, float or double.
#include <gtest/gtest.h>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include "logrid/glm_camera.hpp"
#include "logrid/projection.hpp"

namespace logrid {
namespace {

TEST(GlmCamera, MatricesCopyElementForElementBothWays) {
  glm::dmat4 g(1.0);
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) g[c][r] = 10 * c + r + 0.25;
  }
  const Mat4d m = toMat4d(g);
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) EXPECT_EQ(m(r, c), 10 * c + r + 0.25);
  }
  EXPECT_EQ(toGlm(m), g);
  // A GLM translation keeps its offset in the last column, as logrid's does.
  EXPECT_EQ(toMat4d(glm::translate(glm::mat4(1.0f), glm::vec3(1, 2, 3))).m[13], 2.0);
  const DVec3 v = toDVec3(glm::vec3(0.1f, 2, 3));
  EXPECT_EQ(v.x, double(0.1f));  // widened exactly, not re-rounded to 0.1
  EXPECT_EQ(toGlm(v), glm::dvec3(double(0.1f), 2, 3));
}

// multiply() and translation() work on Mat4d without GLM; they compose a camera as GLM
// did, element for element (its product sums each element's four terms in the same order), so
// that every matrix on a frame's path is what it was when they converted to GLM and back.
TEST(GlmCamera, MultiplyAndTranslationComposeAsGlmDid) {
  const DepthSetup depth{DepthConvention::Reversed, ClipDepthRange::ZeroToOne};
  const Mat4d projection = perspective(1.1, 4.0 / 3.0, 0.1, 700.0, depth);
  const Mat4d view = lookAt({3.3, 1.7, -2.9}, {-1.1, 0.3, 5.7}, {0, 1, 0});
  const DVec3 origin{1234.567, -0.001, 98765.4321};
  const glm::dmat4 expected =
      toGlm(projection) * glm::translate(toGlm(view), glm::dvec3(origin.x, origin.y, origin.z));
  const Mat4d got = multiply(projection, multiply(view, translation(origin)));
  for (int i = 0; i < 16; ++i) {
    EXPECT_EQ(got.m[i], toMat4d(expected).m[i]) << "element " << i;
  }
  EXPECT_EQ(translation(origin).m[12], origin.x);
  EXPECT_EQ(translation(origin).m[14], origin.z);
}

TEST(GlmCamera, ClipRangeFollowsThisTranslationUnitsGlmConfiguration) {
  // Built without GLM_FORCE_DEPTH_ZERO_TO_ONE: glm::perspective targets -1..1.
  EXPECT_EQ(glmClipDepthRange(), ClipDepthRange::NegativeOneToOne);
  const glm::dmat4 p = glm::perspective(1.0, 1.0, 1.0, 10.0);
  const glm::dvec4 near = p * glm::dvec4(0, 0, -1, 1);
  EXPECT_NEAR(near.z / near.w, -1.0, 1e-12);
}

TEST(GlmCamera, CameraFromDoubleMatricesIsProjectionTimesView) {
  const glm::dmat4 projection = glm::perspective(1.0, 4.0 / 3.0, 0.5, 200.0);
  const glm::dmat4 view =
      glm::lookAt(glm::dvec3(3, 4, 5), glm::dvec3(0, 0, -20), glm::dvec3(0, 1, 0));
  const DepthSetup depth{DepthConvention::Standard, glmClipDepthRange(), DepthFormat::D24};
  const Camera camera = cameraFromGlm(projection, view, 640, 480, depth, glm::dvec3(3, 4, 5));
  EXPECT_EQ(validateCamera(camera), "");
  EXPECT_EQ(camera.width, 640u);
  EXPECT_EQ(camera.height, 480u);
  EXPECT_EQ(camera.depth.format, DepthFormat::D24);
  EXPECT_EQ(camera.render_origin.z, 5.0);
  const Mat4d expected = toMat4d(projection * view);
  for (int i = 0; i < 16; ++i) EXPECT_EQ(camera.view_projection.m[i], expected.m[i]) << i;
  // The same camera as logrid's own helpers build, up to rounding.
  const Mat4d own = multiply(perspective(1.0, 4.0 / 3.0, 0.5, 200.0, depth),
                             lookAt({3, 4, 5}, {0, 0, -20}, {0, 1, 0}));
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(camera.view_projection.m[i], own.m[i], 1e-12) << i;
}

TEST(GlmCamera, CameraFromFloatMatricesMultipliesInDouble) {
  const glm::mat4 projection = glm::perspective(1.0f, 1.0f, 0.1f, 1000.0f);
  const glm::mat4 view =
      glm::lookAt(glm::vec3(0.3f, 0.7f, 9.1f), glm::vec3(0.1f, 0.2f, 0.0f), glm::vec3(0, 1, 0));
  const Camera camera = cameraFromGlm(projection, view, 64, 64, {});
  const Mat4d expected = toMat4d(glm::dmat4(projection) * glm::dmat4(view));
  for (int i = 0; i < 16; ++i) EXPECT_EQ(camera.view_projection.m[i], expected.m[i]) << i;
  EXPECT_EQ(camera.render_origin.x, 0.0);
  // And logrid culls with it: a box at the target is inside the view, one behind the eye
  // is not.
  const Projector projector(camera);
  EXPECT_EQ(projector.project({{-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}}).cls,
            ProjectionClass::Inside);
  EXPECT_EQ(projector.project({{0, 0, 20}, {1, 1, 21}}).cls, ProjectionClass::Outside);
}

}  // namespace
}  // namespace logrid
