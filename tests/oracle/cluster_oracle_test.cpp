// Walkthroughs of clustered scenes (samples/scene/clusters.hpp: --cluster N), every frame
// checked against the cluster-level oracle: the ID pass writes each cluster's own id, so
// a visible cluster that was culled is a miss even when another cluster of its object
// was drawn, and the oracle's floor is the exact set of visible clusters.
//
//   ClusterWalk   forest, city, office and a model file; both depth conventions;
//                 log-state, log-zfar, a lookahead with temporal coherence, a query
//                 schedule (chc), the cpu reader, back-face cluster culling, and
//                 movers, clustered, their clusters moving with them.
//   ClusterObjects  the objects the visible clusters belong to are the object-level
//                 oracle's visible objects, frame by frame (the same triangles drawn).
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <tuple>

#include "logrid/error.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "scene/clusters.hpp"

#include "flat_grid.hpp"
#include "oracle_harness.hpp"

namespace logrid::oracle {
namespace {

class ClusterWalk : public testing::TestWithParam<OracleCase> {};

TEST_P(ClusterWalk, NoVisibleClusterIsMissed) {
  LOGRID_REQUIRE_GL();
  checkCase(GetParam());
}

OracleCase clusterCase(const std::string& scene, std::uint32_t cluster,
                       samples::MethodChoice method, DepthConvention convention, DepthFormat format,
                       const std::string& label) {
  OracleCase c;
  c.scene = sceneKey(scene);
  c.scene.cluster = cluster;
  c.method = method;
  c.view.width = 200;
  c.view.height = 150;
  c.view.tile = 16;
  c.view.convention = convention;
  c.view.format = format;
  c.frames = 4;
  c.name = scene + "_c" + std::to_string(cluster) + "_" + label + "_" + toString(convention);
  return c;
}

std::vector<OracleCase> clusterCases() {
  using C = DepthConvention;
  using F = DepthFormat;
  std::vector<OracleCase> out;
  for (const char* scene : {"forest", "city"}) {
    out.push_back(
        clusterCase(scene, 64, choice(Method::LogState), C::Standard, F::D24, "log_state"));
    out.push_back(
        clusterCase(scene, 128, choice(Method::LogZfar), C::Reversed, F::D32F, "log_zfar"));
    out.push_back(clusterCase(scene, 64, choice(Method::LogZfar, 16, true), C::Standard, F::D32F,
                              "log_zfar_16_tc"));
    OracleCase chc =
        clusterCase(scene, 128, choice(Method::Chc), C::Reversed, F::D32F, "chc_consecutive");
    chc.time_step = 1.5;  // consecutive frames: what the schedule carries over
    out.push_back(chc);
    OracleCase cpu =
        clusterCase(scene, 64, choice(Method::LogZfar), C::Reversed, F::D24, "log_zfar_cpu");
    cpu.reader = "cpu";
    out.push_back(cpu);
  }
  out.push_back(
      clusterCase("office", 64, choice(Method::LogState), C::Reversed, F::D32F, "log_state"));
  out.push_back(
      clusterCase("office-file", 128, choice(Method::LogZfar), C::Standard, F::D24, "log_zfar"));
  // The application's renderer culls back faces and skips the clusters facing away.
  for (const auto& [scene, method, label] :
       {std::tuple{"office", choice(Method::LogState), "log_state"},
        std::tuple{"city", choice(Method::LogZfar), "log_zfar"},
        std::tuple{"office", choice(Method::LogZfar, 16, true), "log_zfar_16_tc"},
        std::tuple{"city", choice(Method::Chc), "chc"}}) {
    OracleCase c =
        clusterCase(scene, 64, method, C::Reversed, F::D32F, std::string(label) + "_backfaces");
    c.view.cull_back_faces = true;
    c.adjust = [](RunConfig& config) { config.backface_clusters = true; };
    c.expect_backfacing = true;
    out.push_back(c);
  }
  // Movers clustered beside the static clusters, their clusters moving with them (a
  // motion hierarchy over both); with the cpu reader, whose buffer draws them where
  // they are; in the city with the clusters facing away skipped.
  OracleCase moving =
      clusterCase("forest", 64, choice(Method::LogState), C::Standard, F::D32F, "movers");
  moving.scene.movers = 12;
  moving.time_step = 1.5;
  out.push_back(moving);
  OracleCase moving_cpu =
      clusterCase("forest", 64, choice(Method::LogZfar), C::Reversed, F::D24, "movers_cpu");
  moving_cpu.scene.movers = 12;
  moving_cpu.time_step = 1.5;
  moving_cpu.reader = "cpu";  // the buffer draws each moving cluster where it is
  out.push_back(moving_cpu);
  OracleCase moving_backfaces =
      clusterCase("city", 64, choice(Method::LogZfar), C::Reversed, F::D24, "movers_backfaces");
  moving_backfaces.scene.movers = 200;
  moving_backfaces.time_step = 1.5;
  moving_backfaces.view.cull_back_faces = true;
  moving_backfaces.adjust = [](RunConfig& config) { config.backface_clusters = true; };
  moving_backfaces.expect_backfacing = true;
  out.push_back(moving_backfaces);
  return out;
}

INSTANTIATE_TEST_SUITE_P(Scenes, ClusterWalk, testing::ValuesIn(clusterCases()), oracleCaseName);

// The clustered forest draws the same triangles as the whole one, so the objects with a
// visible cluster are the whole scene's visible objects; the clusters are more, and the
// oracle draws fewer triangles.
TEST(ClusterObjects, TheVisibleClustersObjectsAreTheObjectOraclesObjects) {
  LOGRID_REQUIRE_GL();
  SceneKey whole_key = sceneKey("forest");
  SceneKey cluster_key = whole_key;
  cluster_key.cluster = 64;
  LoadedScene& whole = loadScene(whole_key);
  LoadedScene& clustered = loadScene(cluster_key);
  View view;
  view.width = 200;
  view.height = 150;
  RunConfig config = makeConfig(whole.prepared, Method::LogState, "readpixels", view, 6);
  config.method = samples::MethodChoice{};  // the oracle
  FrameRunner by_object(whole.prepared, *whole.renderer, config);
  FrameRunner by_cluster(clustered.prepared, *clustered.renderer, config);
  std::uint64_t visible_clusters = 0, visible_objects = 0, cluster_triangles = 0,
                object_triangles = 0;
  for (std::size_t f = 0; f < config.frames; ++f) {
    const FrameRecord o = by_object.renderFrame(f);
    const FrameRecord c = by_cluster.renderFrame(f);
    EXPECT_EQ(c.visible_objects, o.visible) << "frame " << f;
    EXPECT_EQ(c.objects_drawn, o.visible) << "frame " << f;
    EXPECT_EQ(o.visible_objects, -1);  // no clusters: the ids are the objects
    visible_clusters += std::uint64_t(c.visible);
    visible_objects += std::uint64_t(o.visible);
    cluster_triangles += c.triangles;
    object_triangles += o.triangles;
  }
  EXPECT_GT(visible_objects, 0u);
  EXPECT_GT(visible_clusters, visible_objects);
  EXPECT_LT(cluster_triangles, object_triangles);
  std::printf(
      "[ oracle ] forest, %zu frames: %llu visible objects, %llu visible clusters; "
      "oracle triangles %llu by object, %llu by cluster\n",
      config.frames, (unsigned long long)visible_objects, (unsigned long long)visible_clusters,
      (unsigned long long)object_triangles, (unsigned long long)cluster_triangles);
}

// The clusters of a scene whose visible set GL's back-face culling decides, and how
// many of those the cone test says face away: over `frames` frames of the oracle (which
// draws what the ID pass saw), with back faces culled or not.
struct Facing {
  std::uint64_t visible = 0, facing_away = 0;
  std::uint64_t moving_visible = 0;  // of them, clusters of movers
};
Facing visibleFacingAway(LoadedScene& scene, bool cull, std::size_t frames) {
  View view;
  view.width = 200;
  view.height = 150;
  RunConfig config = makeConfig(scene.prepared, Method::LogState, "readpixels", view, frames);
  config.method = samples::MethodChoice{};  // the oracle
  config.view.cull_back_faces = cull;
  FrameRunner runner(scene.prepared, *scene.renderer, config);
  Facing out;
  for (std::size_t f = 0; f < config.frames; ++f) {
    runner.renderFrame(f);
    const DVec3 eye = runner.cameraFor(f).render_origin;
    for (ObjectId id : runner.drawnObjects()) {
      out.facing_away += samples::clusterFacesAway(scene.prepared, runner.motionFrame(), id, eye);
      ++out.visible;
      out.moving_visible += id >= scene.prepared.static_objects;
    }
  }
  return out;
}

// The cone test against GL itself: where back faces are culled no visible cluster is
// said to face away, on the scenes (the city's vehicles' clusters turned and moved with
// them) and on an open surface seen from behind.
TEST(ClusterBackfaces, NoVisibleClusterFacesAwayWhereGlCullsBackFaces) {
  LOGRID_REQUIRE_GL();
  for (const auto& [name, movers] : {std::pair{"forest", 0u}, {"city", 200u}, {"office", 0u}}) {
    SceneKey key = sceneKey(name, movers);
    key.cluster = 64;
    const Facing f = visibleFacingAway(loadScene(key), true, 8);
    std::printf(
        "[ oracle ] %s, back faces culled: %llu of %llu visible clusters (%llu moving) face "
        "away\n",
        name, (unsigned long long)f.facing_away, (unsigned long long)f.visible,
        (unsigned long long)f.moving_visible);
    EXPECT_EQ(f.facing_away, 0u) << name;
    EXPECT_GT(f.visible, 0u) << name;
    if (movers) {
      EXPECT_GT(f.moving_visible, 0u) << name << ": no mover seen; the check tests none";
    }
  }
}

// The flat grid seen from below: without back-face culling its clusters are visible and
// face away (skipping them would miss: FrameRunner refuses it); with it, GL shows none.
TEST(ClusterBackfaces, AnOpenSurfaceSeenFromBehindIsVisibleOnlyWithoutCulling) {
  LOGRID_REQUIRE_GL();
  samples::Scene grid = test::flatGrid(32);
  grid.path = samples::CameraPath({{{4, -6, 2}, {16, 0, 16}, 0}, {{28, -8, 4}, {16, 0, 20}, 1}});
  grid.near_plane = 0.1;
  grid.far_plane = 200;
  LoadedScene scene;
  samples::ClusterOptions clusters;
  clusters.triangles = 64;
  scene.prepared =
      samples::prepareScene(std::move(grid), samples::defaultBuildArgs(grid), clusters);
  scene.renderer = std::make_unique<gl::MeshRenderer>(scene.prepared.mesh);
  const Facing open = visibleFacingAway(scene, false, 4);
  const Facing culled = visibleFacingAway(scene, true, 4);
  EXPECT_GT(open.visible, 0u);
  EXPECT_GT(open.facing_away, 0u) << "the cone test never fired; the check tests nothing";
  EXPECT_EQ(culled.visible, 0u);
  EXPECT_EQ(culled.facing_away, 0u);
}

// Sub-pixel snapping can turn a thin triangle seen from behind to face the eye, which
// facesAway() does not allow for (clusters.hpp: it bounds GL's float error, not the
// snapping of each vertex to the sub-pixel grid). A triangle in a plane seen from
// behind at 0.0187 radians (the cone's cutoff is 0.01), every angle's sine at least
// 0.032, placed so that its window corners lie 0.49 to 0.51 of a 1/256-pixel step on
// either side of a row of pixel centres: exact arithmetic has it clockwise (a back
// face), llvmpipe's snapped corners counter-clockwise, and with back faces culled GL
// draws 3 pixels of the cluster that facesAway() says it culls. Disabled until the
// cone test bounds the snapping (it needs the view's pixel scale); run it with
// --gtest_also_run_disabled_tests.
TEST(ClusterBackfaces, DISABLED_ATriangleSnappedToFaceTheEyeIsNotSkipped) {
  LOGRID_REQUIRE_GL();
  Camera cam;
  cam.width = 64;
  cam.height = 64;
  cam.view_projection = multiply(perspective(1.0, 1.0, 0.1, 100, cam.depth),
                                 lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}));
  const double pixels = 32.0 / std::tan(0.5);  // per unit of x / -z
  // The point of the plane through (0, 0, -10) with normal (0, cos b, -sin b),
  // sin b = 0.0102, that the eye sees at window (x, y).
  const double sin_b = 0.0102, cos_b = std::sqrt(1 - sin_b * sin_b);
  std::vector<float> positions;
  auto add = [&](double x, double y) {
    const double dx = (x - 32) / pixels, dy = (y - 32) / pixels;
    const double t = 10 * sin_b / (dy * cos_b + sin_b);
    positions.insert(positions.end(), {float(t * dx), float(t * dy), float(-t)});
  };
  const double step = 1.0 / 256, row = 32.5;  // llvmpipe's sub-pixel step; a centre row
  add(40.3, row + 0.49 * step);
  add(43.3, row - 0.49 * step);
  add(37.3, row + 0.51 * step);
  const std::uint32_t triangle[] = {0, 1, 2};  // clockwise on screen: seen from behind
  samples::ClusterOptions options;
  options.triangles = 4;
  samples::ClusterBuilder builder(positions.data(), 3, options);
  std::vector<std::uint32_t> indices;
  const std::vector<samples::Cluster> clusters = builder.build(triangle, 3, indices);
  ASSERT_EQ(clusters.size(), 1u);
  ASSERT_TRUE(samples::facesAway(clusters[0].cone, {0, 0, 0}));

  gl::RenderMesh mesh;
  mesh.positions = positions;
  mesh.indices32 = indices;
  mesh.draws.push_back({0, 3, 0, 0xFFFFFFFFu});
  gl::MeshRenderer renderer(mesh);
  renderer.setCullBackFaces(true);
  gl::Framebuffer fb({cam.width, cam.height, cam.depth, false});
  fb.bind();
  const float black[4] = {0, 0, 0, 1};
  fb.clear(black);
  renderer.begin(gl::Pass::Shaded, cam);
  renderer.draw(0);
  renderer.end();
  const std::vector<std::uint8_t> color = fb.readColor();
  std::size_t drawn = 0;
  for (std::size_t i = 0; i < color.size(); i += 4) drawn += (color[i] | color[i + 1]) != 0;
  EXPECT_EQ(drawn, 0u) << "GL drew " << drawn << " pixels of a cluster facesAway() skips";
}

TEST(ClusterBackfaces, SkippingIsRefusedWhereItCouldMiss) {
  LOGRID_REQUIRE_GL();
  SceneKey key = sceneKey("forest");
  key.cluster = 64;
  LoadedScene& clustered = loadScene(key);
  LoadedScene& whole = loadScene(sceneKey("forest"));
  auto refused = [](LoadedScene& scene, const std::function<void(RunConfig&)>& set,
                    const char* needle) {
    RunConfig config = makeConfig(scene.prepared, Method::LogState, "readpixels", View{}, 1);
    set(config);
    try {
      FrameRunner runner(scene.prepared, *scene.renderer, config);
      ADD_FAILURE() << "accepted; expected a refusal naming " << needle;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  refused(
      clustered, [](RunConfig& c) { c.backface_clusters = true; }, "--cull-back-faces");
  refused(
      whole,
      [](RunConfig& c) {
        c.backface_clusters = true;
        c.view.cull_back_faces = true;
      },
      "--cluster");
  refused(
      clustered,
      [](RunConfig& c) {
        c.backface_clusters = true;
        c.view.cull_back_faces = true;
        c.view.orthographic = true;
      },
      "--ortho");
  refused(
      clustered,
      [](RunConfig& c) {
        c.view.cull_back_faces = true;
        c.reader = "cpu";
      },
      "--reader cpu");
}

}  // namespace
}  // namespace logrid::oracle
