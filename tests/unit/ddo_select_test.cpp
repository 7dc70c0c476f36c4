// The DDO run time (DDO §4): the octree walk, the occlusion map and the occluders,
// checked on small scenes against a software render of every triangle: no object the
// selector leaves out shows a pixel, and every pixel an occluder claims is covered by
// geometry in front of it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <set>

#include "ddo_scenes.hpp"
#include "expect_status.hpp"
#include "logrid/cpu/software_rasterizer.hpp"
#include "logrid/ddo/build.hpp"
#include "logrid/ddo/occluder_pass.hpp"
#include "logrid/ddo/selector.hpp"
#include "logrid/grid.hpp"

namespace logrid {
namespace {

using test::TriangleScene;

// Rows of welded walls with boxes behind and between them: something to hide behind.
TriangleScene streetScene(std::uint32_t seed) {
  TriangleScene s;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int row = 0; row < 4; ++row) {
    TriangleScene::WallOptions o;
    o.n = 8;
    if (row == 2) o.skip_i = 3, o.skip_j = 1;  // a window to see through
    const double z = -6.0 + 4.0 * row + unit(rng);
    s.wall(2, z, -10, 10, 0, 6, o);  // walls at constant z, x in [-10, 10], y in [0, 6]
    for (int b = 0; b < 6; ++b) {
      const double x = -9 + 18 * unit(rng), zz = z + 0.6 + 2 * unit(rng);
      const double lo[3] = {x - 0.5, 0, zz - 0.5}, hi[3] = {x + 0.5, 1 + 3 * unit(rng), zz + 0.5};
      s.box(lo, hi);
    }
  }
  TriangleScene::WallOptions ground;
  ground.n = 10;
  s.wall(1, -0.01, -12, 12, -12, 12, ground);  // a ground at y = -0.01 (u = z, v = x)
  return s;
}

// The octree the tests select from: 24-triangle leaves.
ddo::Octree streetOctree(const TriangleScene& s) {
  ddo::BuildArgs args;
  args.leaf_triangles = 24;
  args.threads = 2;
  return ddo::buildOctree(s.mesh(), args);
}

Camera cameraAt(const DVec3& eye, const DVec3& target, DepthConvention convention) {
  Camera c;
  c.width = 160;
  c.height = 120;
  c.depth = {convention,
             convention == DepthConvention::Reversed ? ClipDepthRange::ZeroToOne
                                                     : ClipDepthRange::NegativeOneToOne,
             DepthFormat::D32F};
  const Mat4d proj = perspective(60.0 * M_PI / 180.0, 160.0 / 120.0, 0.1, 200.0, c.depth);
  c.view_projection = multiply(proj, lookAt(eye, target, {0, 1, 0}));
  c.render_origin = eye;
  return c;
}

struct Render {
  cpu::SoftwareDepthBuffer depth;
  std::vector<std::uint32_t> ids;
  Render(const Camera& c)
      : depth(c.width, c.height, c.depth.convention),
        ids(std::size_t(c.width) * c.height, cpu::kNoId) {
    depth.clear();
  }
};

// Renders every triangle of the scene with its object's id.
Render renderAll(const TriangleScene& s, const Camera& camera) {
  Render r(camera);
  cpu::SoftwareRasterizer raster(camera, r.depth, &r.ids, cpu::Coverage::Inclusive);
  for (std::uint32_t o = 0; o + 1 < s.object_first.size(); ++o) {
    for (std::uint32_t t = s.object_first[o]; t < s.object_first[o + 1]; ++t) {
      raster.drawTriangle(&s.positions[s.indices[t * 3] * 3],
                          &s.positions[s.indices[t * 3 + 1] * 3],
                          &s.positions[s.indices[t * 3 + 2] * 3], o);
    }
  }
  return r;
}

class DdoSelect : public testing::TestWithParam<DepthConvention> {};

TEST_P(DdoSelect, CulledObjectsAreHiddenAndOccludersLieBehindTheGeometry) {
  const DepthConvention convention = GetParam();
  std::uint64_t culled_nodes = 0, occluders = 0, hidden_objects = 0, claimed_pixels = 0;
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    const TriangleScene s = streetScene(seed);
    const ddo::Octree octree = streetOctree(s);
    ddo::Selector selector(octree);
    std::mt19937 rng(seed * 7);
    std::uniform_real_distribution<double> x(-9, 9), z(-12, 14), y(0.5, 5);
    for (int view = 0; view < 24; ++view) {
      const DVec3 eye{x(rng), y(rng), view % 2 ? 14.0 + 4 * z(rng) / 14 : z(rng)};
      const DVec3 target{x(rng), y(rng) * 0.5, z(rng)};
      const Camera camera = cameraAt(eye, target, convention);
      std::set<ObjectId> drawn;
      ddo::SelectionStats stats;
      selector.select(
          camera, [&](ObjectId id) { drawn.insert(id); }, stats);
      culled_nodes += stats.nodes_occluded;
      occluders += selector.occluders().size();
      const Render full = renderAll(s, camera);
      std::set<ObjectId> visible;
      for (std::uint32_t id : full.ids) {
        if (id != cpu::kNoId) visible.insert(id);
      }
      for (ObjectId id : visible) {
        EXPECT_TRUE(drawn.count(id)) << "seed " << seed << " view " << view << ": object " << id
                                     << " is visible but was culled";
      }
      hidden_objects += (s.object_first.size() - 1) - drawn.size();
      // Every map pixel an occluder claims holds geometry in front of the occluder.
      const ddo::OcclusionMap& map = selector.map();
      const float clear = convention == DepthConvention::Reversed ? 0.0f : 1.0f;
      for (std::uint32_t py = 0; py < camera.height; ++py) {
        for (std::uint32_t px = 0; px < camera.width; ++px) {
          const float claimed = map.key(px, py);
          if (claimed >= depthKey(convention, clear)) continue;
          ++claimed_pixels;
          const float rendered = depthKey(convention, full.depth.at(px, py));
          EXPECT_LT(rendered, claimed)
              << "seed " << seed << " view " << view << " pixel " << px << ", " << py
              << ": an occluder claims key " << claimed << " where the geometry is at " << rendered;
        }
      }
    }
  }
  EXPECT_GT(culled_nodes, 20u) << "the map never culled anything: the test is vacuous";
  EXPECT_GT(occluders, 20u);
  EXPECT_GT(hidden_objects, 20u);
  EXPECT_GT(claimed_pixels, 10000u);
}

INSTANTIATE_TEST_SUITE_P(Conventions, DdoSelect,
                         testing::Values(DepthConvention::Standard, DepthConvention::Reversed),
                         [](const testing::TestParamInfo<DepthConvention>& p) {
                           return std::string(toString(p.param));
                         });

// Without the map and a draw callback (ddo+log) the walk skips, unprojected, subtrees
// that hold no face valid from any region: the same occluders as a walk that visits them.
TEST(DdoSelect, AWalkForFacesAloneSkipsFacelessSubtreesAndSelectsTheSame) {
  const ddo::Octree octree = streetOctree(streetScene(2));
  ddo::SelectorSettings settings;
  settings.occlusion_map = false;
  ddo::Selector faces_only(octree, settings), every_node(octree, settings);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(-9, 9), z(-12, 14), y(0.5, 5);
  std::uint64_t skipped = 0, occluders = 0;
  for (int view = 0; view < 24; ++view) {
    const Camera camera =
        cameraAt({x(rng), y(rng), z(rng)}, {x(rng), y(rng) * 0.5, z(rng)},
                 view % 2 ? DepthConvention::Reversed : DepthConvention::Standard);
    ddo::SelectionStats a, b;
    faces_only.select(camera, {}, a);
    every_node.select(
        camera, [](ObjectId) {}, b);  // a callback: every node is visited
    EXPECT_EQ(b.nodes_faceless, 0u);
    EXPECT_LT(a.nodes_visited, b.nodes_visited) << "view " << view;
    skipped += a.nodes_faceless;
    ASSERT_EQ(faces_only.occluders().size(), every_node.occluders().size()) << "view " << view;
    for (std::size_t i = 0; i < faces_only.occluders().size(); ++i) {
      const ddo::Occluder& p = faces_only.occluders()[i];
      const ddo::Occluder& q = every_node.occluders()[i];
      EXPECT_EQ(std::memcmp(p.window, q.window, sizeof p.window), 0) << "view " << view;
      EXPECT_EQ(p.far_key, q.far_key);
      EXPECT_EQ(p.faces, q.faces);
    }
    occluders += faces_only.occluders().size();
  }
  EXPECT_GT(skipped, 0u);
  EXPECT_GT(occluders, 20u) << "no occluder selected: the comparison is vacuous";
}

TEST(DdoSelectMap, OccludesOnlyWhenEveryPixelIsNearer) {
  ddo::OcclusionMap map;
  map.reset(64, 48, 1.0f);
  const double quad[4][2] = {{10, 10}, {40, 10}, {40, 30}, {10, 30}};
  EXPECT_EQ(map.insertQuad(quad, 0.5, 0, 0), 30u * 20u);
  EXPECT_TRUE(map.occludes({12, 12, 38, 28}, 0.6f));
  EXPECT_FALSE(map.occludes({12, 12, 38, 28}, 0.5f));  // equal keys: not behind
  EXPECT_FALSE(map.occludes({5, 12, 38, 28}, 0.6f));   // reaches past the quad
  // A sloped occluder: key grows with x.
  map.reset(64, 48, 1.0f);
  map.insertQuad(quad, 0.1, 0.01, 0);
  EXPECT_TRUE(map.occludes({10, 10, 20, 30}, 0.31f));   // keys up to 0.1 + 0.195
  EXPECT_FALSE(map.occludes({10, 10, 40, 30}, 0.31f));  // up to 0.495 on the right
}

}  // namespace
}  // namespace logrid

namespace logrid {
namespace {

// ddo+log's occluder pass draws the occluders that pay (OccluderBudget): each drawn one
// fills at least min_tiles grid tiles, the most filling first, never more triangles than
// the cap; it announces each drawn occluder's area and outline.
TEST(DdoOccluderPass, DrawsTheOccludersThatFillTilesMostFirstUnderTheCap) {
  const ddo::Octree octree = streetOctree(streetScene(2));
  std::size_t drawn_calls = 0;
  const ddo::OccluderPass::Drawer drawer = [&](const std::vector<ddo::Occluder>&, const Camera&) {
    ++drawn_calls;
    return Status();
  };
  ddo::OccluderBudget every;
  every.min_tiles = 0;
  every.max_triangles = 1u << 20;
  ddo::OccluderBudget paying;
  paying.tile_size = 16;
  ddo::OccluderBudget capped = paying;
  capped.max_triangles = 4;  // two quads
  ddo::OccluderPass all(octree, drawer, {}, every), pays(octree, drawer, {}, paying),
      cap(octree, drawer, {}, capped);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(-9, 9), z(-12, 14), y(0.5, 5);
  std::uint64_t candidates = 0, filling = 0, left_out = 0;
  for (int view = 0; view < 24; ++view) {
    const Camera camera = cameraAt({x(rng), y(rng), 14.0 + 4 * z(rng) / 14},
                                   {x(rng), y(rng) * 0.5, z(rng)}, DepthConvention::Standard);
    std::vector<DrawnArea> areas;
    const std::uint64_t n_all = orThrow(all.beginFrame(camera, {}, true, areas));
    EXPECT_EQ(n_all, all.passStats().candidates);  // no cap, no minimum: everything
    EXPECT_EQ(areas.size(), n_all);
    EXPECT_EQ(all.drawnQuads().size(), n_all);
    areas.clear();
    const std::uint64_t n_pays = orThrow(pays.beginFrame(camera, {}, true, areas));
    EXPECT_EQ(areas.size(), n_pays);
    ASSERT_EQ(pays.drawnQuads().size(), n_pays);
    const CoverageRule rule = coverageRule(camera);
    std::vector<std::uint32_t> fills;
    for (const DrawnQuad& q : pays.drawnQuads()) {
      OcclusionGrid grid({camera.width, camera.height, 16, GridVariant::OcclusionState});
      grid.reset(clearKey(camera.depth));
      fills.push_back(grid.recordCovered(q, rule));
      EXPECT_GE(fills.back(), 1u) << "view " << view << ": an occluder filling no tile was drawn";
    }
    EXPECT_TRUE(std::is_sorted(fills.rbegin(), fills.rend())) << "most tiles first";
    std::uint64_t total = 0;
    for (std::uint32_t f : fills) total += f;
    EXPECT_EQ(total, pays.passStats().tiles_filled);
    areas.clear();
    const std::uint64_t n_cap = orThrow(cap.beginFrame(camera, {}, true, areas));
    EXPECT_EQ(n_cap, std::min<std::uint64_t>(n_pays, 2));
    for (std::size_t i = 0; i < n_cap; ++i) {
      EXPECT_EQ(cap.drawnQuads()[i].far_key, pays.drawnQuads()[i].far_key);
    }
    candidates += n_all;
    filling += n_pays;
    left_out += n_all - n_pays;
  }
  EXPECT_GT(filling, 10u) << "no occluder filled a tile: the test is vacuous";
  EXPECT_GT(left_out, 0u) << "every occluder filled a tile: the minimum was never tested";
  std::printf("[ ddo pass ] %llu candidates, %llu fill a tile\n", (unsigned long long)candidates,
              (unsigned long long)filling);
}

// The pass's errors come back from beginFrame() (OccluderSource's result form): an
// invalid camera and the drawer's own error. Without a drawer, the quads are chosen for
// the culler to record and nothing is drawn or announced (ddo+log).
TEST(DdoOccluderPass, BeginFrameReturnsTheErrors) {
  const ddo::Octree octree = streetOctree(streetScene(2));
  ddo::OccluderBudget every;
  every.min_tiles = 0;
  ddo::OccluderPass map_only(octree);
  std::vector<DrawnArea> areas;
  const Camera camera = cameraAt({0, 2, 18}, {0, 1, 0}, DepthConvention::Standard);
  ddo::OccluderPass recorded(octree, {}, {}, every);
  const Result<std::uint64_t> chosen = recorded.beginFrame(camera, {}, true, areas);
  ASSERT_TRUE(chosen.ok()) << chosen.status().message();
  EXPECT_GT(*chosen, 0u);
  EXPECT_EQ(recorded.drawnQuads().size(), *chosen);
  EXPECT_TRUE(areas.empty()) << "nothing was drawn, so nothing is announced";
  Camera broken = camera;
  broken.width = 0;
  test::expectStatus(map_only.beginFrame(broken, {}, false, areas).status(),
                     ErrorCode::InvalidArgument, {"camera: viewport 0x120"});
  // The selector's two forms agree.
  ddo::Selector selector(octree);
  ddo::SelectionStats stats;
  test::expectBothForms([&] { return selector.trySelect(broken, {}, stats); },
                        [&] { selector.select(broken, {}, stats); }, ErrorCode::InvalidArgument,
                        {"camera: viewport 0x120"});
  // A drawer that fails: its error, as it gave it.
  const ddo::OccluderPass::Drawer failing = [](const std::vector<ddo::Occluder>&, const Camera&) {
    return Status(ErrorCode::Runtime, "drawer: GL error 0x505");
  };
  ddo::OccluderPass pass(octree, failing, {}, every);
  const Result<std::uint64_t> selected = map_only.beginFrame(camera, {}, false, areas);
  ASSERT_TRUE(selected.ok()) << selected.status().message();
  ASSERT_GT(map_only.selector().occluders().size(), 0u) << "nothing to draw: the test is vacuous";
  const Result<std::uint64_t> drawn = pass.beginFrame(camera, {}, true, areas);
  test::expectStatus(drawn.status(), ErrorCode::Runtime, {"drawer: GL error 0x505"});
}

}  // namespace
}  // namespace logrid
