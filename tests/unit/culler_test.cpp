// The whole culler without GL: random box scenes drawn by the software rasteriser,
// checked against an object-ID pass of the full scene. Every method, both conventions,
// several tile sizes and resolutions: no visible object may be missed.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "box_world.hpp"
#include "logrid/bvh/bvh.hpp"
#include "logrid/cpu/software_rasterizer.hpp"
#include "logrid/culler.hpp"
#include "logrid/error.hpp"

namespace logrid {
namespace {

using test::BoxWorld;
using Scene = BoxWorld;

Scene makeScene(std::uint32_t seed) { return test::makeBoxWorld(seed); }

Camera makeCamera(std::uint32_t w, std::uint32_t h, DepthConvention convention, double yaw) {
  return test::boxCamera(w, h, convention, yaw);
}

struct Outcome {
  std::set<ObjectId> visible;
  std::set<ObjectId> drawn;
  FrameStats stats;
};

Outcome runFrame(const Scene& scene, const Camera& cam, const CullerDesc& desc, bool count_only) {
  Outcome out;
  out.visible = test::visibleBoxes(scene.boxes, cam);
  cpu::SoftwareDepthBuffer depth(cam.width, cam.height, cam.depth.convention);
  Culler culler(desc);
  const test::CulledFrame f =
      test::cullBoxes(culler, scene, cam, depth,
                      count_only ? test::SourceKind::CountOnly : test::SourceKind::Software);
  out.drawn = f.drawn;
  out.stats = f.stats;
  return out;
}

struct Case {
  Method method;
  DepthConvention convention;
};

class CullerOracleTest : public testing::TestWithParam<Case> {};

TEST_P(CullerOracleTest, NeverMissesAVisibleObject) {
  const Case c = GetParam();
  const Scene scene = makeScene(11);
  std::size_t drawn = 0, visible = 0, vfc_drawn = 0;
  for (std::uint32_t tile : {1u, 7u, 32u}) {
    for (auto [w, h] : {std::pair<std::uint32_t, std::uint32_t>{64, 48}, {161, 97}}) {
      for (double yaw : {-0.6, 0.0, 0.4}) {
        const Camera cam = makeCamera(w, h, c.convention, yaw);
        const Outcome o = runFrame(scene, cam, {c.method, tile, {}, {}}, false);
        for (ObjectId id : o.visible) {
          EXPECT_TRUE(o.drawn.count(id)) << "visible object " << id << " was culled (tile " << tile
                                         << ", " << w << "x" << h << ", yaw " << yaw << ")";
        }
        drawn += o.drawn.size();
        visible += o.visible.size();
        vfc_drawn += runFrame(scene, cam, {Method::Vfc, tile, {}, {}}, false).drawn.size();
      }
    }
  }
  std::printf("[ oracle ] %s %s: drawn %zu, visible %zu, vfc drawn %zu\n", toString(c.method),
              toString(c.convention), drawn, visible, vfc_drawn);
  if (c.method != Method::Vfc) {
    EXPECT_LT(drawn * 2, vfc_drawn) << "occlusion culling should at least halve the draws here";
  }
}

TEST_P(CullerOracleTest, PredicateOnlySourceNeverMissesEither) {
  const Case c = GetParam();
  if (c.method == Method::Hzb) GTEST_SKIP() << "hzb needs a source that reads pixels";
  const Scene scene = makeScene(12);
  for (double yaw : {-0.3, 0.2}) {
    const Camera cam = makeCamera(120, 90, c.convention, yaw);
    const Outcome o = runFrame(scene, cam, {c.method, 16, {}, {}}, true);
    for (ObjectId id : o.visible) EXPECT_TRUE(o.drawn.count(id)) << "object " << id;
  }
}

std::string caseName(const testing::TestParamInfo<Case>& param) {
  std::string s =
      std::string(toString(param.param.method)) + "_" + toString(param.param.convention);
  for (char& ch : s) ch = ch == '-' ? '_' : ch;
  return s;
}

INSTANTIATE_TEST_SUITE_P(AllMethods, CullerOracleTest,
                         testing::Values(Case{Method::LogState, DepthConvention::Standard},
                                         Case{Method::LogState, DepthConvention::Reversed},
                                         Case{Method::LogZfar, DepthConvention::Standard},
                                         Case{Method::LogZfar, DepthConvention::Reversed},
                                         Case{Method::Bog, DepthConvention::Standard},
                                         Case{Method::Bog, DepthConvention::Reversed},
                                         Case{Method::Hzb, DepthConvention::Standard},
                                         Case{Method::Hzb, DepthConvention::Reversed},
                                         Case{Method::Pq, DepthConvention::Standard},
                                         Case{Method::Pq, DepthConvention::Reversed},
                                         Case{Method::Vfc, DepthConvention::Standard}),
                         caseName);

// A hierarchy that hands back one NaN box among valid ones.
class BrokenHierarchy : public Hierarchy {
 public:
  NodeId root() const override { return 0; }
  Aabb bounds(NodeId n) const override {
    if (n == 2) return {{NAN, 0, 0}, {1, 1, 1}};
    return {{-1, -1, -11}, {1, 1, -9}};
  }
  std::uint32_t childCount(NodeId n) const override { return n == 0 ? 2 : 0; }
  NodeId child(NodeId, std::uint32_t i) const override { return i + 1; }
  std::uint32_t objectCount(NodeId n) const override { return n == 0 ? 0 : 1; }
  ObjectId object(NodeId n, std::uint32_t) const override { return n; }
};

TEST(CullerTest, InvalidBoxesAreDrawnAndCounted) {
  const Camera cam = makeCamera(64, 48, DepthConvention::Standard, 0);
  cpu::SoftwareDepthBuffer depth(64, 48, DepthConvention::Standard);
  Culler culler({Method::LogState, 8, {}, {}});
  std::set<ObjectId> drawn;
  const FrameStats s =
      culler.cullFrame(cam, BrokenHierarchy(), depth, [&](ObjectId id) { drawn.insert(id); });
  EXPECT_EQ(s.invalid_boxes, 1u);
  EXPECT_TRUE(drawn.count(2));
}

TEST(CullerTest, BadCameraAndBadDescriptorsThrow) {
  Camera cam = makeCamera(64, 48, DepthConvention::Standard, 0);
  cpu::SoftwareDepthBuffer depth(64, 48, DepthConvention::Standard);
  Culler culler;
  const bvh::FlatHierarchy h = bvh::buildOverBoxes({{{-1, -1, -11}, {1, 1, -9}}});
  cam.view_projection.m[0] = INFINITY;
  EXPECT_THROW(culler.cullFrame(cam, h, depth, [](ObjectId) {}), Error);
  cam = makeCamera(32, 48, DepthConvention::Standard, 0);  // buffer is 64x48
  EXPECT_THROW(culler.cullFrame(cam, h, depth, [](ObjectId) {}), Error);
  EXPECT_THROW(Culler({Method::LogZfar, 0, {}, {}}), Error);
  EXPECT_EQ(parseMethod("log-zfar"), Method::LogZfar);
  EXPECT_FALSE(parseMethod("fast").has_value());
}

TEST(CullerTest, HzbRefusesAPredicateOnlySource) {
  const Camera cam = makeCamera(64, 48, DepthConvention::Standard, 0);
  cpu::SoftwareDepthBuffer depth(64, 48, DepthConvention::Standard);
  test::CountOnlySource queries(depth);
  Culler culler({Method::Hzb, 8, {}, {}});
  const bvh::FlatHierarchy h = bvh::buildOverBoxes({{{-1, -1, -11}, {1, 1, -9}}});
  EXPECT_THROW(culler.cullFrame(cam, h, queries, [](ObjectId) {}), Error);
}

TEST(CullerTest, EmptyHierarchyDrawsNothing) {
  const Camera cam = makeCamera(64, 48, DepthConvention::Standard, 0);
  cpu::SoftwareDepthBuffer depth(64, 48, DepthConvention::Standard);
  Culler culler;
  const FrameStats s = culler.cullFrame(cam, bvh::buildOverBoxes({}), depth,
                                        [](ObjectId) { ADD_FAILURE() << "nothing to draw"; });
  EXPECT_EQ(s.objects_drawn, 0u);
}

}  // namespace
}  // namespace logrid
