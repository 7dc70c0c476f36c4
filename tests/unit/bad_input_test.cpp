// Bad input at logrid's API boundary. Every case ends either in a logrid::Error whose
// code fits and whose message names what failed and what to do, or in the answer
// "visible" (the object is drawn, and counted in FrameStats::invalid_boxes): never a
// silent cull, a crash or a hang. Errors are asserted on their code and on parts of
// their message; visible answers on the objects drawn and the statistics.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "expect_error.hpp"
#include "logrid/grid.hpp"
#include "logrid/bvh/bvh.hpp"
#include "logrid/cpu/software_depth.hpp"
#include "logrid/culler.hpp"
#include "logrid/error.hpp"

namespace logrid {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr Method kAllMethods[] = {Method::LogState, Method::LogZfar, Method::Bog,
                                  Method::Hzb,      Method::Pq,      Method::Vfc};

using test::expectError;

// Eye at the origin looking down -z, near 0.5, far 100.
Camera camera(std::uint32_t w = 64, std::uint32_t h = 48, DepthSetup depth = {}) {
  Camera cam;
  cam.width = w;
  cam.height = h;
  cam.depth = depth;
  cam.view_projection = perspective(1.0, double(w) / h, 0.5, 100, depth);
  return cam;
}

CullerDesc descFor(Method method, std::uint32_t tile_size = 8) {
  CullerDesc desc;
  desc.method = method;
  desc.tile_size = tile_size;
  return desc;
}

// A wall 5 ahead filling the view (object 0) and a box hidden behind it (object 1).
struct WallScene {
  std::vector<Aabb> boxes = {{{-50, -50, -5}, {50, 50, -5}}, {{-1, -1, -12}, {1, 1, -10}}};
  bvh::FlatHierarchy hierarchy = bvh::buildOverBoxes(boxes);
};

// One frame: drawing object 0 fills the software buffer with the wall's window depth.
FrameStats cullWall(const Camera& cam, const Hierarchy& hierarchy, const CullerDesc& desc,
                    std::set<ObjectId>& drawn) {
  cpu::SoftwareDepthBuffer depth(cam.width, cam.height, cam.depth.convention);
  Culler culler(desc);
  // Window depth of distance 5 for near 0.5, far 100 and the -1..1 range.
  const float wall = float(0.5 * ((100.5 / 99.5) - 100.0 / (99.5 * 5)) + 0.5);
  return culler.cullFrame(cam, hierarchy, depth, [&](ObjectId id) {
    drawn.insert(id);
    if (id == 0) depth.fillRect({0, 0, std::int32_t(cam.width), std::int32_t(cam.height)}, wall);
  });
}

// Runs one frame of a culler over a one-box hierarchy with `cam`, for the error cases.
void cullOnce(const Camera& cam, const CullerDesc& desc = {}) {
  const bvh::FlatHierarchy h = bvh::buildOverBoxes({{{-1, -1, -11}, {1, 1, -9}}});
  cpu::SoftwareDepthBuffer depth(64, 48, DepthConvention::Standard);
  Culler culler(desc);
  culler.cullFrame(cam, h, depth, [](ObjectId) {});
}

// ---------------------------------------------------------------------------------------
// Cameras
// ---------------------------------------------------------------------------------------

TEST(BadCameraTest, NonFiniteMatrixElementsAreErrors) {
  for (int element : {0, 5, 10, 11, 14, 15}) {
    for (double value : {double(kNaN), double(kInf), -double(kInf)}) {
      Camera cam = camera();
      cam.view_projection.m[element] = value;
      expectError([&] { cullOnce(cam); }, ErrorCode::InvalidArgument,
                  {"view_projection element " + std::to_string(element), "must be finite"});
    }
  }
  Camera cam = camera();
  cam.view_projection.m[3] = cam.view_projection.m[7] = cam.view_projection.m[11] =
      cam.view_projection.m[15] = 0;
  expectError([&] { cullOnce(cam); }, ErrorCode::InvalidArgument,
              {"all-zero bottom row", "pass projection * view"});
  cam = camera();
  cam.render_origin = {0, double(kNaN), 0};
  expectError([&] { cullOnce(cam); }, ErrorCode::InvalidArgument, {"render_origin", "finite"});
}

TEST(BadCameraTest, ViewportSizesOutOfRangeAreErrors) {
  const std::uint32_t minus_one = static_cast<std::uint32_t>(-1);  // a negative size, cast
  const std::pair<std::uint32_t, std::uint32_t> sizes[] = {
      {0, 48}, {64, 0}, {0, 0}, {minus_one, 48}, {100000, 100000}, {kMaxViewportSide + 1, 1}};
  for (auto [w, h] : sizes) {
    Camera cam = camera();
    cam.width = w;
    cam.height = h;
    expectError([&] { cullOnce(cam); }, ErrorCode::InvalidArgument,
                {"viewport " + std::to_string(w) + "x" + std::to_string(h),
                 "between 1 and " + std::to_string(kMaxViewportSide)});
    expectError([&] { cpu::SoftwareDepthBuffer(w, h, DepthConvention::Standard); },
                ErrorCode::InvalidArgument,
                {"size " + std::to_string(w) + "x" + std::to_string(h), "out of range"});
  }
}

// The extremes that are valid work with every method: a 1 x 1 view and a 32768 x 1 one.
TEST(BadCameraTest, ExtremeButValidViewportsWork) {
  for (auto [w, h] : {std::pair<std::uint32_t, std::uint32_t>{1, 1}, {kMaxViewportSide, 1}}) {
    const Camera cam = camera(w, h);
    const WallScene scene;
    for (Method method : kAllMethods) {
      SCOPED_TRACE(std::string(toString(method)) + " " + std::to_string(w) + "x" +
                   std::to_string(h));
      std::set<ObjectId> drawn;
      cullWall(cam, scene.hierarchy, descFor(method), drawn);
      EXPECT_TRUE(drawn.count(0));
    }
  }
}

TEST(BadCameraTest, DepthSetupNonsenseIsAnError) {
  // Planes: near <= 0 or not below far, NaN, infinite where not allowed.
  const DepthSetup standard;
  const std::pair<double, double> planes[] = {
      {0, 10}, {-1, 10}, {1, 1}, {2, 1}, {1, -kInf}, {kNaN, 10}, {0.1, double(kNaN)}, {kInf, kInf}};
  for (auto [n, f] : planes) {
    expectError([&] { perspective(1.0, 1.0, n, f, standard); }, ErrorCode::InvalidArgument,
                {"perspective: near", "need 0 < near < far"});
  }
  for (auto [n, f] : {std::pair<double, double>{1, 1}, {2, 1}, {0, kInf}, {kNaN, 1}}) {
    expectError([&] { orthographic(-1, 1, -1, 1, n, f, standard); }, ErrorCode::InvalidArgument,
                {"orthographic: near", "need near < far, both finite"});
  }
  for (auto [fovy, aspect] : {std::pair<double, double>{0, 1},
                              {M_PI, 1},
                              {kNaN, 1},
                              {-1, 1},
                              {1, 0},
                              {1, -1},
                              {1, kInf},
                              {1, kNaN}}) {
    expectError([&] { perspective(fovy, aspect, 0.1, 10, standard); }, ErrorCode::InvalidArgument,
                {"perspective: fovy", "need 0 < fovy < pi"});
  }
  expectError([&] { orthographic(1, 1, 0, 1, 0, 1, standard); }, ErrorCode::InvalidArgument,
              {"need left < right and bottom < top"});
  expectError(
      [&] {
        lookAt({0, 0, 0}, {0, 0, 0}, {0, 1, 0});
      },
      ErrorCode::InvalidArgument, {"lookAt", "eye != target"});
  expectError(
      [&] {
        lookAt({kNaN, 0, 0}, {0, 0, -1}, {0, 1, 0});
      },
      ErrorCode::InvalidArgument, {"lookAt", "finite"});

  // The depth set-up of the camera itself.
  Camera cam = camera();
  cam.depth.convention = DepthConvention::Reversed;  // with the default -1..1 range
  expectError([&] { cullOnce(cam); }, ErrorCode::InvalidArgument,
              {"reversed depth needs the zero-to-one clip range", "ClipDepthRange::ZeroToOne"});
  cam = camera();
  cam.depth.format = static_cast<DepthFormat>(7);
  expectError([&] { cullOnce(cam); }, ErrorCode::InvalidArgument,
              {"depth.format has the unknown value 7", "D32F"});
  cam = camera();
  cam.depth.convention = static_cast<DepthConvention>(5);
  expectError([&] { cullOnce(cam); }, ErrorCode::InvalidArgument,
              {"depth.convention has the unknown value 5"});
  cam = camera();
  cam.depth.clip_range = static_cast<ClipDepthRange>(9);
  expectError([&] { cullOnce(cam); }, ErrorCode::InvalidArgument,
              {"depth.clip_range has the unknown value 9"});
}

// ---------------------------------------------------------------------------------------
// Culler and projection settings
// ---------------------------------------------------------------------------------------

// An unknown method names the value and the names to use; a grid with more tiles than
// kMaxGridTiles (a 32768 x 32768 viewport with 1-pixel tiles would need some 74 GB) is
// an error suggesting a larger tile size, not std::bad_alloc. Only the validators are
// called, so the test allocates nothing.
TEST(BadSettingsTest, UnknownMethodAndHugeGridsAreClearErrors) {
  CullerDesc desc;
  desc.method = static_cast<Method>(42);
  const std::string method = validateCullerDesc(desc);
  EXPECT_NE(method.find("42"), std::string::npos) << method;
  EXPECT_NE(method.find("log-state"), std::string::npos) << method;
  const std::string grid =
      validateGridDesc({kMaxViewportSide, kMaxViewportSide, 1, GridVariant::OcclusionState});
  EXPECT_NE(grid.find("tile size"), std::string::npos) << "'" << grid << "'";
}

TEST(BadSettingsTest, TileSizeZeroIsAnErrorAndAbsurdTileSizesWork) {
  expectError([] { Culler c(descFor(Method::LogState, 0)); }, ErrorCode::InvalidArgument,
              {"tile size 0 is invalid", "use 1 pixel or more"});
  const Camera cam = camera();
  const WallScene scene;
  for (std::uint32_t tile : {1u, 63u, 64u, 100000u, 1u << 31, ~0u}) {
    for (Method method : kAllMethods) {
      SCOPED_TRACE(std::string(toString(method)) + " tile " + std::to_string(tile));
      std::set<ObjectId> drawn;
      cullWall(cam, scene.hierarchy, descFor(method, tile), drawn);
      EXPECT_TRUE(drawn.count(0));
      // The grid stays exact whatever its tiles: the box behind the wall is culled.
      if (method != Method::Vfc) {
        EXPECT_FALSE(drawn.count(1));
      }
    }
  }
}

TEST(BadSettingsTest, ProjectionSettingsOutOfRangeAreErrors) {
  EXPECT_EQ(validateProjectionSettings({}), "");
  struct Case {
    ProjectionSettings settings;
    std::string part;
  };
  const double nan = std::nan(""), inf = INFINITY;
  const Case cases[] = {{{kRenderErrorUlps, 1.0, -1}, "subpixel_bits -1 is out of range"},
                        {{kRenderErrorUlps, 1.0, 17}, "subpixel_bits 17 is out of range"},
                        {{nan, 1.0, 4}, "render_error_ulps nan is invalid"},
                        {{-1.0, 1.0, 4}, "render_error_ulps -1 is invalid"},
                        {{inf, 1.0, 4}, "render_error_ulps inf is invalid"},
                        {{kRenderErrorUlps, nan, 4}, "quantisation_scale nan is invalid"},
                        {{kRenderErrorUlps, -0.5, 4}, "quantisation_scale -0.5 is invalid"},
                        {{kRenderErrorUlps, inf, 4}, "quantisation_scale inf is invalid"}};
  for (const Case& c : cases) {
    EXPECT_NE(validateProjectionSettings(c.settings).find(c.part), std::string::npos);
    CullerDesc desc;
    desc.projection = c.settings;
    expectError([&] { cullOnce(camera(), desc); }, ErrorCode::InvalidArgument, {c.part, "use"});
  }
}

// ---------------------------------------------------------------------------------------
// Boxes in a hierarchy
// ---------------------------------------------------------------------------------------

// Node 0: root (valid, around everything). Its children: 1, the wall (valid, 5 ahead,
// filling the view); 2 to 7, leaves with NaN, infinite and inverted boxes, all lying
// behind the wall if they were anything; 8, an inner node with a NaN box whose one child,
// 9, is a valid box hidden behind the wall. Object ids equal node ids.
class BadBoxHierarchy : public Hierarchy {
 public:
  NodeId root() const override { return 0; }
  Aabb bounds(NodeId n) const override {
    switch (n) {
      case 0: return {{-60, -60, -60}, {60, 60, -1}};
      case 1: return {{-50, -50, -5}, {50, 50, -5}};
      case 2: return {{kNaN, -1, -12}, {1, 1, -10}};
      case 3: return {{-1, -1, -12}, {1, 1, kNaN}};
      case 4: return {{-1, -1, -12}, {kInf, 1, -10}};
      case 5: return {{-1, -kInf, -12}, {1, 1, -10}};
      case 6: return {{1, -1, -12}, {-1, 1, -10}};   // min.x > max.x
      case 7: return {{-1, -1, -10}, {1, 1, -12}};   // min.z > max.z
      case 8: return {{-1, -1, kNaN}, {1, 1, -10}};  // inner
      default: return {{-1, -1, -12}, {1, 1, -10}};  // 9: valid, behind the wall
    }
  }
  std::uint32_t childCount(NodeId n) const override { return n == 0 ? 8 : n == 8 ? 1 : 0; }
  NodeId child(NodeId n, std::uint32_t i) const override { return n == 0 ? 1 + i : 9; }
  std::uint32_t objectCount(NodeId n) const override { return n == 0 || n == 8 ? 0 : 1; }
  ObjectId object(NodeId n, std::uint32_t) const override { return n; }
};

TEST(BadBoxTest, NonFiniteAndInvertedBoxesAreDrawnAndCounted) {
  const Camera cam = camera();
  for (Method method : kAllMethods) {
    SCOPED_TRACE(toString(method));
    std::set<ObjectId> drawn;
    const FrameStats s = cullWall(cam, BadBoxHierarchy(), descFor(method), drawn);
    for (ObjectId bad = 2; bad <= 7; ++bad) EXPECT_TRUE(drawn.count(bad)) << "object " << bad;
    EXPECT_TRUE(drawn.count(1));
    EXPECT_EQ(s.invalid_boxes, 7u);   // six leaves and the inner node 8
    EXPECT_EQ(s.nodes_visited, 10u);  // the child of the invalid inner node is reached
    // Node 9 is valid: with occlusion culling it may be culled behind the wall.
    if (method == Method::Vfc) {
      EXPECT_TRUE(drawn.count(9));
    }
  }
}

// Huge but finite boxes are valid: one around everything contains the eye and is drawn,
// one far beyond the far plane is view-culled, and nothing overflows.
TEST(BadBoxTest, HugeFiniteBoxesAreClassifiedNotLost) {
  const float big = std::numeric_limits<float>::max();
  const std::vector<Aabb> boxes = {{{-50, -50, -5}, {50, 50, -5}},
                                   {{-big, -big, -big}, {big, big, big}},
                                   {{-1e30f, -1e30f, -big}, {1e30f, 1e30f, -1e30f}}};
  const bvh::FlatHierarchy h = bvh::buildOverBoxes(boxes);
  for (Method method : kAllMethods) {
    SCOPED_TRACE(toString(method));
    std::set<ObjectId> drawn;
    const FrameStats s = cullWall(camera(), h, descFor(method), drawn);
    EXPECT_TRUE(drawn.count(1));
    EXPECT_FALSE(drawn.count(2));
    EXPECT_GE(s.boxes_near, 1u);
    EXPECT_EQ(s.invalid_boxes, 0u);
  }
}

// ---------------------------------------------------------------------------------------
// Hierarchy builders
// ---------------------------------------------------------------------------------------

TEST(BadBvhInputTest, NonFiniteOrInvertedBoxesAreErrors) {
  const Aabb good{{0, 0, 0}, {1, 1, 1}};
  for (const Aabb& bad : {Aabb{{kNaN, 0, 0}, {1, 1, 1}}, Aabb{{0, 0, 0}, {1, kInf, 1}},
                          Aabb{{0, 0, -kInf}, {1, 1, 1}}, Aabb{{0, 2, 0}, {1, 1, 1}}}) {
    expectError(
        [&] {
          bvh::buildOverBoxes({good, good, bad});
        },
        ErrorCode::BadInput,
        {"bvh: object 2 has an invalid box", "boxes must be finite with min <= max"});
    // Refitting to such a box is the same error, and leaves the hierarchy as it was.
    bvh::FlatHierarchy h = bvh::buildOverBoxes({good, good, good});
    const Aabb before = h.bounds(h.root());
    expectError(
        [&] {
          h.refit({good, bad, good});
        },
        ErrorCode::BadInput,
        {"refit: object 1 has an invalid box", "boxes must be finite with min <= max"});
    EXPECT_EQ(h.bounds(h.root()).max.x, before.max.x);
  }
  bvh::FlatHierarchy h = bvh::buildOverBoxes({good, good, good});
  expectError([&] { h.refit({good}); }, ErrorCode::InvalidArgument, {"object 1 has no box"});
}

TEST(BadBvhInputTest, NonFiniteVerticesAndBadIndicesAreErrors) {
  const std::vector<std::uint32_t> tri = {0, 1, 2};
  expectError(
      [&] {
        bvh::buildOverTriangles({0, 0, 0, 1, kNaN, 0, 0, 1, 0}, tri);
      },
      ErrorCode::BadInput,
      {"vertex 1 has a non-finite coordinate (y = nan)", "positions must be finite"});
  expectError(
      [&] {
        bvh::buildOverTriangles({0, 0, 0, 1, 0, 0, 0, 1, -kInf}, tri);
      },
      ErrorCode::BadInput, {"vertex 2 has a non-finite coordinate (z = -inf)"});
  expectError(
      [&] {
        bvh::buildOverTriangles({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 9});
      },
      ErrorCode::BadInput, {"triangle 0 uses vertex 9 but there are only 3 vertices"});
  expectError(
      [&] {
        bvh::buildOverTriangles({0, 0, 0, 1}, tri);
      },
      ErrorCode::BadInput, {"must come in threes"});
  expectError(
      [&] {
        bvh::buildOverBoxes({}, {0, 2, 0});
      },
      ErrorCode::InvalidArgument, {"max_leaf_size 0 is invalid", "use 1 or more"});
  expectError(
      [&] {
        bvh::buildOverTriangles({}, {}, {1, 3, 0});
      },
      ErrorCode::InvalidArgument, {"max_children 3 is invalid", "use 2, 4 or 8"});
  expectError(
      [&] {
        bvh::buildOverBoxes({}, {1, 2, 5000});
      },
      ErrorCode::InvalidArgument, {"threads 5000 is out of range", "use"});
  // Empty input is valid: an empty hierarchy, which culls to nothing.
  const bvh::TriangleHierarchy empty = bvh::buildOverTriangles({}, {});
  EXPECT_EQ(empty.hierarchy.root(), kNoNode);
  std::set<ObjectId> drawn;
  cullWall(camera(), empty.hierarchy, descFor(Method::LogState), drawn);
  EXPECT_TRUE(drawn.empty());
}

}  // namespace
}  // namespace logrid
