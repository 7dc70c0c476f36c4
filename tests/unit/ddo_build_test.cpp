// The DDO preprocessing (DDO §3): region geometry, the octree, and the validity test,
// checked against brute force: every face marked valid for a region is hidden behind the
// scene's triangles from every sampled viewpoint of the region.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ddo_scenes.hpp"
#include "expect_error.hpp"
#include "expect_status.hpp"
#include "logrid/ddo/build.hpp"
#include "logrid/error.hpp"

namespace logrid {
namespace {

using test::TriangleScene;

// ---------------------------------------------------------------------------
// Regions (figure 3) and the viewspace frustum (figure 4).
// ---------------------------------------------------------------------------

TEST(DdoRegions, LayoutsOf32And64) {
  ASSERT_TRUE(ddo::RegionLayout::forCount(64));
  ASSERT_TRUE(ddo::RegionLayout::forCount(32));
  EXPECT_FALSE(ddo::RegionLayout::forCount(16));
  EXPECT_EQ(ddo::RegionLayout::forCount(64)->count(), 64u);
  EXPECT_EQ(ddo::RegionLayout::forCount(32)->count(), 32u);
  for (std::uint32_t bins : {4u, 8u}) {
    EXPECT_EQ(ddo::RegionLayout::edge(bins, bins / 2), 0.0);
    for (std::uint32_t i = 0; i < bins; ++i) {
      EXPECT_LT(ddo::RegionLayout::edge(bins, i), ddo::RegionLayout::edge(bins, i + 1));
    }
    EXPECT_NEAR(ddo::RegionLayout::edge(bins, bins), std::tan(80.0 * M_PI / 180.0), 1e-12);
  }
  int first = 0, last = 0;
  ddo::RegionLayout::binsMeeting(8, 0.1, 0.2, first, last);
  EXPECT_EQ(first, 4);
  EXPECT_EQ(last, 4);
  ddo::RegionLayout::binsMeeting(8, -0.1, 0.1, first, last);
  EXPECT_EQ(first, 3);
  EXPECT_EQ(last, 4);
  ddo::RegionLayout::binsMeeting(8, 6.0, 7.0, first, last);  // beyond 80 degrees
  EXPECT_GT(first, last);
}

// Every segment from a viewpoint of a region to a point of the enlarged face, cut at the
// clipping plane, lies inside P(face, region): the derivation in regions.hpp.
TEST(DdoRegions, SegmentsFromTheRegionStayInsideTheFrustum) {
  std::mt19937 rng(3);
  const auto layout = *ddo::RegionLayout::forCount(64);
  const double lo[3] = {1.0, -2.0, 0.5}, side = 2.0;
  const double hi[3] = {lo[0] + side, lo[1] + side, lo[2] + side};
  std::uniform_real_distribution<double> unit(0, 1);
  for (int face = 0; face < ddo::kFaces; ++face) {
    const ddo::FaceFrame f = ddo::faceFrame(lo, hi, side, face);
    for (std::uint32_t r = 0; r < layout.count(); ++r) {
      const ddo::ViewspaceFrustum p(f, layout.cell(r));
      for (int s = 0; s < 40; ++s) {
        double v[3], q[3];
        test::regionViewpoint(f, layout.cell(r), rng, s % 4 == 0, v);
        test::facePoint(f, rng, s % 3, q);
        const double hv = f.heightOf(v);
        ASSERT_GE(hv, f.height * (1 - 1e-12));
        // Points of the segment up to the clipping plane.
        for (int k = 0; k <= 8; ++k) {
          const double t = (f.height / hv) * k / 8.0;
          double x[3];
          for (int a = 0; a < 3; ++a) x[a] = q[a] + t * (v[a] - q[a]);
          for (int i = 0; i < 6; ++i) {
            const double g = p.n[i][0] * x[0] + p.n[i][1] * x[1] + p.n[i][2] * x[2] + p.c[i];
            ASSERT_GE(g, -1e-9) << "face " << face << " region " << r << " plane " << i;
          }
        }
        const double top[3] = {q[0] + (f.height / hv) * (v[0] - q[0]),
                               q[1] + (f.height / hv) * (v[1] - q[1]),
                               q[2] + (f.height / hv) * (v[2] - q[2])};
        EXPECT_TRUE(p.meetsSegment(q, top, 1e-9));
      }
    }
  }
}

TEST(DdoRegions, FrustumMeetsSegments) {
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  const ddo::FaceFrame f = ddo::faceFrame(lo, hi, 1.0, 4);  // z low face, viewer at z > 1
  const ddo::ViewspaceFrustum p(f, {-0.1, 0.1, -0.1, 0.1});
  const double in_a[3] = {0.5, 0.5, 0.5}, in_b[3] = {0.6, 0.4, 0.2};
  EXPECT_TRUE(p.meetsSegment(in_a, in_b, 0));
  const double through_a[3] = {-5, 0.5, 0.5}, through_b[3] = {5, 0.5, 0.5};
  EXPECT_TRUE(p.meetsSegment(through_a, through_b, 0));
  const double above_a[3] = {0.5, 0.5, 1.5}, above_b[3] = {0.2, 0.2, 3};  // beyond H
  EXPECT_FALSE(p.meetsSegment(above_a, above_b, 0));
  const double beside_a[3] = {2.0, -1, 0.5}, beside_b[3] = {2.0, 2, 0.5};
  EXPECT_FALSE(p.meetsSegment(beside_a, beside_b, 0));
}

// ---------------------------------------------------------------------------
// The octree (§3.1).
// ---------------------------------------------------------------------------

TEST(DdoOctree, SubdividesToTheLeafThresholdAndKeepsEveryTriangle) {
  TriangleScene s;
  std::mt19937 rng(11);
  s.clutter(rng, 300, 0, 10, 0.3);
  s.clutter(rng, 200, 4, 6, 0.2);
  ddo::BuildArgs args;
  args.leaf_triangles = 16;
  args.threads = 2;
  ddo::BuildReport report;
  const ddo::Octree o = ddo::buildOctree(s.mesh(), args, {}, &report);
  ASSERT_FALSE(o.empty());
  EXPECT_EQ(o.nodes().front().triangle_count, 500u);
  std::uint64_t leaf_triangles = 0;
  for (std::uint32_t n = 0; n < o.nodes().size(); ++n) {
    const ddo::OctreeNode& node = o.nodes()[n];
    double lo[3], hi[3];
    o.cellBox(n, lo, hi);
    if (node.leaf()) {
      leaf_triangles += node.triangle_count;
      EXPECT_LE(node.triangle_count, args.leaf_triangles);
      EXPECT_GE(node.object_count, 1u);
    } else {
      std::uint32_t sum = 0;
      for (int k = 0; k < 8; ++k) {
        const std::uint32_t c = o.child(n, k);
        if (c == ddo::Octree::kNone) continue;
        sum += o.nodes()[c].triangle_count;
        EXPECT_EQ(o.nodes()[c].level, node.level + 1);
        // The child's tight box lies inside the parent's.
        const Aabb& cb = o.nodes()[c].bounds;
        EXPECT_GE(cb.min.x, node.bounds.min.x);
        EXPECT_LE(cb.max.z, node.bounds.max.z);
        double clo[3], chi[3];
        o.cellBox(c, clo, chi);
        for (int a = 0; a < 3; ++a) {
          EXPECT_EQ(clo[a],
                    ((k >> a) & 1) ? o.plane(a, node.level + 1u, 2ull * node.cell[a] + 1) : lo[a]);
          EXPECT_DOUBLE_EQ(chi[a] - clo[a], o.side(node.level + 1u));
        }
      }
      EXPECT_EQ(sum, node.triangle_count);
    }
  }
  EXPECT_EQ(leaf_triangles, 500u);
  EXPECT_EQ(report.nodes, o.nodes().size());
  EXPECT_GT(report.leaves, 8u);
  EXPECT_EQ(o.maskBytes(), o.nodes().size() * 6 * 8);
}

TEST(DdoOctree, BadInputIsRefusedClearly) {
  TriangleScene s;
  s.triangle(s.vertex(0, 0, 0), s.vertex(1, 0, 0), s.vertex(0, 1, 0));
  s.endObject();
  ddo::BuildArgs args;
  args.regions = 48;
  test::expectError([&] { ddo::buildOctree(s.mesh(), args); }, ErrorCode::InvalidArgument,
                    {"regions 48"});
  TriangleScene bad = s;
  bad.indices[2] = 7;
  test::expectError([&] { ddo::buildOctree(bad.mesh()); }, ErrorCode::BadInput, {"uses vertex 7"});
  TriangleScene nan = s;
  nan.positions[4] = std::nanf("");
  test::expectError([&] { ddo::buildOctree(nan.mesh()); }, ErrorCode::BadInput, {"non-finite"});
  TriangleScene runs = s;
  runs.object_first = {0, 5};
  test::expectError([&] { ddo::buildOctree(runs.mesh()); }, ErrorCode::BadInput, {"object runs"});
}

// The result form: tryBuildOctree() returns the error buildOctree() throws.
TEST(DdoOctree, TryBuildReturnsWhatBuildThrows) {
  TriangleScene s;
  s.triangle(s.vertex(0, 0, 0), s.vertex(1, 0, 0), s.vertex(0, 1, 0));
  s.endObject();
  ddo::BuildArgs args;
  args.max_depth = 30;
  test::expectBothForms([&] { return ddo::tryBuildOctree(s.mesh(), args); },
                        [&] { ddo::buildOctree(s.mesh(), args); }, ErrorCode::InvalidArgument,
                        {"ddo: max_depth 30 is out of range"});
  TriangleScene bad = s;
  bad.indices[1] = 9;
  test::expectBothForms([&] { return ddo::tryBuildOctree(bad.mesh()); },
                        [&] { ddo::buildOctree(bad.mesh()); }, ErrorCode::BadInput,
                        {"uses vertex 9"});
  args = {};
  args.threads = 1;
  const Result<ddo::Octree> built = ddo::tryBuildOctree(s.mesh(), args);
  ASSERT_TRUE(built.ok()) << built.status().message();
  EXPECT_FALSE(built->nodes().empty());
}

// ---------------------------------------------------------------------------
// Validity (§3.2).
// ---------------------------------------------------------------------------

ddo::BuildArgs smallArgs(std::uint32_t leaf = 8) {
  ddo::BuildArgs args;
  args.leaf_triangles = leaf;
  args.threads = 2;
  return args;
}

// The node whose cell contains `p` at the given level, or kNone.
std::uint32_t nodeAt(const ddo::Octree& o, const double* p, std::uint32_t level) {
  std::uint32_t n = 0;
  while (o.nodes()[n].level < level) {
    int octant = 0;
    const ddo::OctreeNode& node = o.nodes()[n];
    for (int a = 0; a < 3; ++a) {
      if (p[a] >= o.plane(a, node.level + 1u, 2ull * node.cell[a] + 1)) octant |= 1 << a;
    }
    n = o.child(n, octant);
    if (n == ddo::Octree::kNone) return n;
  }
  return n;
}

// A wall through the middle of a cell, far wider than the cell: the cell's far face is
// hidden from the near side for every region whose frustum the wall spans.
struct WallScene {
  TriangleScene scene;
  ddo::Octree octree;
  std::uint32_t node = ddo::Octree::kNone;
  double z = 0;
};

WallScene wallScene(const TriangleScene::WallOptions& o, double wall_half_width = 40) {
  WallScene w;
  // Clutter far away decides the root; a wall at z = 0.37 spans x, y in +-wall_half_width.
  std::mt19937 rng(5);
  w.scene.clutter(rng, 64, -64, -60, 0.5);
  w.scene.clutter(rng, 64, 60, 64, 0.5);
  w.z = 0.37;
  w.scene.wall(2, w.z, -wall_half_width, wall_half_width, -wall_half_width, wall_half_width, o);
  w.octree = ddo::buildOctree(w.scene.mesh(), smallArgs(8));
  return w;
}

TEST(DdoValidity, WallHidesTheFarFaceFromTheNearSide) {
  TriangleScene::WallOptions o;
  o.n = 20;
  WallScene w = wallScene(o);
  // Find the smallest node holding the wall's centre and check its low-z face.
  std::uint32_t n = 0, found = ddo::Octree::kNone;
  for (std::uint32_t level = 0;; ++level) {
    const double p[3] = {0.1, 0.1, w.z};
    n = nodeAt(w.octree, p, level);
    if (n == ddo::Octree::kNone) break;
    double lo[3], hi[3];
    w.octree.cellBox(n, lo, hi);
    if (lo[2] < w.z && w.z < hi[2]) found = n;
  }
  ASSERT_NE(found, ddo::Octree::kNone);
  const std::uint64_t low_z = w.octree.mask(found, 4), high_z = w.octree.mask(found, 5);
  // Viewed from above (region of slope 0 in the middle), the low face is behind the wall;
  // the wall is within the slab of the high face too (viewed from below).
  const auto& layout = w.octree.layout();
  const std::uint32_t centre = layout.region(4, 4);
  EXPECT_TRUE((low_z >> centre) & 1u) << std::hex << low_z;
  EXPECT_TRUE((high_z >> centre) & 1u) << std::hex << high_z;
  // The faces perpendicular to the wall are never hidden by it.
  for (int f = 0; f < 4; ++f) EXPECT_EQ(w.octree.mask(found, f), 0u) << "face " << f;
  const test::BruteForceResult r = test::bruteForceCheck(w.scene, w.octree, 800, 24);
  EXPECT_EQ(r.unblocked, 0u);
  EXPECT_GT(r.checked_bits, 100u);
}

TEST(DdoValidity, HoleOrCrackInTheWallInvalidatesTheFacesAboveIt) {
  TriangleScene::WallOptions whole;
  whole.n = 20;
  const WallScene intact = wallScene(whole);
  TriangleScene::WallOptions holed = whole;
  holed.skip_i = 10;  // the quad at x in [0, 4], y in [0, 4]
  holed.skip_j = 10;
  const WallScene with_hole = wallScene(holed);
  TriangleScene::WallOptions cracked = whole;
  cracked.crack_column = 10;  // a seam at x = 0
  cracked.crack = 1e-3;
  const WallScene with_crack = wallScene(cracked);
  TriangleScene::WallOptions welded = whole;
  welded.crack_column = 10;  // duplicated vertices at the same positions: welded
  welded.crack = 0;
  const WallScene with_seam = wallScene(welded);

  auto validAt = [](const WallScene& w, double x, double y) {
    std::uint64_t bits = 0;
    for (std::uint32_t level = 0;; ++level) {
      const double p[3] = {x, y, w.z};
      const std::uint32_t n = nodeAt(w.octree, p, level);
      if (n == ddo::Octree::kNone) break;
      bits |= w.octree.mask(n, 4);
    }
    return bits;
  };
  // The four regions around the normal: their frustums hold the hole and the seam of
  // every face above them (oblique regions may look past a seam at the face's edge).
  const auto& layout = intact.octree.layout();
  std::uint64_t central = 0;
  for (std::uint32_t b1 : {3u, 4u}) {
    for (std::uint32_t b2 : {3u, 4u}) central |= std::uint64_t{1} << layout.region(b1, b2);
  }
  EXPECT_EQ(validAt(intact, 1.0, 1.0) & central, central);
  EXPECT_EQ(validAt(with_hole, 1.0, 1.0) & central, 0u) << "a face above the hole was valid";
  EXPECT_EQ(validAt(with_crack, 0.01, 1.0) & central, 0u) << "a face over the seam was valid";
  EXPECT_EQ(validAt(with_seam, 0.01, 1.0), validAt(intact, 0.01, 1.0))
      << "welding by position must close a seam of duplicated vertices";
  for (const WallScene* w : {&with_hole, &with_crack, &with_seam}) {
    const test::BruteForceResult r = test::bruteForceCheck(w->scene, w->octree, 500, 24);
    EXPECT_EQ(r.unblocked, 0u);
    EXPECT_GT(r.checked_bits, 50u);
  }
}

// A wall narrower than the frustum of the oblique regions: those are not valid, and
// brute force agrees with the ones that are.
TEST(DdoValidity, NarrowWallIsValidOnlyWhereItSpansTheFrustum) {
  TriangleScene::WallOptions o;
  o.n = 6;
  const WallScene w = wallScene(o, 3.0);
  const test::BruteForceResult r = test::bruteForceCheck(w.scene, w.octree, 5000, 32);
  EXPECT_EQ(r.unblocked, 0u);
  std::uint64_t all = 0, full = 0;
  for (std::uint32_t n = 0; n < w.octree.nodes().size(); ++n) {
    for (int f = 0; f < 6; ++f) {
      all += w.octree.mask(n, f) != 0;
      full += w.octree.mask(n, f) == ~std::uint64_t{0};
    }
  }
  EXPECT_GT(all, 0u);
  EXPECT_EQ(full, 0u) << "a narrow wall cannot hide a face from 80-degree views";
}

// A closed box is crossed twice by every line through it, yet each of its two sheets
// inside a frustum is a surface of its own: a thick wall hides what is behind it.
TEST(DdoValidity, ThickClosedWallIsValid) {
  TriangleScene s;
  std::mt19937 rng(9);
  s.clutter(rng, 64, -64, -60, 0.5);
  s.clutter(rng, 64, 60, 64, 0.5);
  const double lo[3] = {-40, -40, 0.3}, hi[3] = {40, 40, 0.45};
  s.box(lo, hi);
  const ddo::Octree o = ddo::buildOctree(s.mesh(), smallArgs(8));
  std::uint64_t valid_faces = 0;
  for (std::uint32_t n = 0; n < o.nodes().size(); ++n) {
    valid_faces += (o.mask(n, 4) != 0) + (o.mask(n, 5) != 0);
  }
  EXPECT_GT(valid_faces, 0u);
  const test::BruteForceResult r = test::bruteForceCheck(s, o, 3000, 24);
  EXPECT_EQ(r.unblocked, 0u);
}

// Soundness on scenes with everything mixed: walls on all three axes (some with holes),
// closed boxes, and random triangles, with both region layouts.
class DdoRandomScenes : public testing::TestWithParam<std::uint32_t> {};

TEST_P(DdoRandomScenes, EveryValidFaceIsHiddenFromItsRegion) {
  const std::uint32_t regions = GetParam();
  std::uint64_t checked = 0;
  for (std::uint32_t seed = 1; seed <= 4; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(-8, 8), len(2, 12);
    TriangleScene s;
    for (int w = 0; w < 5; ++w) {
      TriangleScene::WallOptions o;
      o.n = 3 + int(rng() % 6);
      if (rng() % 2) o.skip_i = int(rng() % unsigned(o.n)), o.skip_j = int(rng() % unsigned(o.n));
      const double u = pos(rng), v = pos(rng), lu = len(rng), lv = len(rng);
      s.wall(int(rng() % 3), pos(rng), u - lu, u + lu, v - lv, v + lv, o);
    }
    for (int b = 0; b < 4; ++b) {
      const double c[3] = {pos(rng), pos(rng), pos(rng)};
      const double lo[3] = {c[0] - 1.5, c[1] - 0.2, c[2] - 2.5},
                   hi[3] = {c[0] + 1.5, c[1] + 0.2, c[2] + 2.5};
      s.box(lo, hi);
    }
    s.clutter(rng, 120, -9, 9, 0.6);
    ddo::BuildArgs args = smallArgs(12);
    args.regions = regions;
    const ddo::Octree o = ddo::buildOctree(s.mesh(), args);
    const test::BruteForceResult r = test::bruteForceCheck(s, o, 1500, 24, seed);
    EXPECT_EQ(r.unblocked, 0u) << "seed " << seed;
    checked += r.checked_bits;
  }
  EXPECT_GT(checked, 200u) << "the random scenes hardly have a valid face: the check is vacuous";
}

INSTANTIATE_TEST_SUITE_P(Layouts, DdoRandomScenes, testing::Values(64u, 32u));

}  // namespace
}  // namespace logrid
