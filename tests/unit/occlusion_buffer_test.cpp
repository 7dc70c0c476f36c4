// The CPU occlusion buffer without GL: welding and adjacency, the SIMD kernels against
// the scalar one, and the conservative property against a reference rasteriser that
// snaps vertices and interpolates depth as GL rasterisers may (snapping_rasterizer.hpp):
// the buffer never holds a key nearer than the reference stores, at any resolution, in
// either convention and every format; with a conservative rule switched off it does.
#include <gtest/gtest.h>

#include <random>

#include "expect_error.hpp"
#include "logrid/cpu/occlusion_buffer.hpp"
#include "logrid/error.hpp"
#include "occluder_scenes.hpp"
#include "snapping_rasterizer.hpp"

namespace logrid {
namespace {

using cpu::OccluderMeshes;
using cpu::OcclusionBuffer;
using cpu::OcclusionBufferDesc;
using test::TestMesh;

OccluderMeshes meshesOf(const std::vector<TestMesh>& scene) {
  OccluderMeshes m;
  for (const TestMesh& t : scene) {
    m.addObject(t.positions.data(), t.positions.size() / 3, t.indices.data(), t.indices.size());
  }
  return m;
}

// Every key of the buffer at viewport resolution after drawing every object (moved by
// transforms[i] where given).
std::vector<float> render(const OccluderMeshes& meshes, const Camera& cam,
                          const OcclusionBufferDesc& desc,
                          const std::vector<cpu::ObjectTransform>* transforms = nullptr) {
  OcclusionBuffer buffer(meshes, desc);
  orThrow(buffer.beginFrame(cam));
  for (std::uint32_t i = 0; i < meshes.objectCount(); ++i) {
    if (transforms) {
      buffer.drawObject(i, (*transforms)[i]);
    } else {
      buffer.drawObject(i);
    }
  }
  std::vector<float> keys(std::size_t(cam.width) * cam.height);
  buffer.readKeys({0, 0, std::int32_t(cam.width), std::int32_t(cam.height)}, keys.data());
  orThrow(buffer.endFrame());
  return keys;
}

TEST(OccluderMeshesTest, WeldsBitIdenticalPositionsAndFindsSharedEdges) {
  // Two quads side by side with their own vertices: welded, the seam becomes shared.
  const TestMesh wall = test::seamedWall(0, 0, 0, 2, 2);
  OccluderMeshes m;
  m.addObject(wall.positions.data(), wall.positions.size() / 3, wall.indices.data(),
              wall.indices.size());
  EXPECT_EQ(m.vertexCount(), 9u);  // 16 positions, 9 distinct
  EXPECT_EQ(m.triangleCount(), 8u);
  std::size_t shared = 0;
  for (std::uint32_t a : m.adjacency()) shared += a != cpu::kNoNeighbour;
  // 2x2 quads, each split in two: 4 diagonals + 4 seams, each counted from both sides.
  EXPECT_EQ(shared, 16u);
  for (std::size_t e = 0; e < m.adjacency().size(); ++e) {
    const std::uint32_t n = m.adjacency()[e];
    if (n != cpu::kNoNeighbour) {
      EXPECT_EQ(m.adjacency()[n], e);
    }
  }
}

TEST(OccluderMeshesTest, ClosedMeshesShareEveryEdgeAndFinsFormARing) {
  const TestMesh s = test::sphere(0, 0, 0, 1, 1, 1, 8, 5);
  OccluderMeshes m;
  m.addObject(s.positions.data(), s.positions.size() / 3, s.indices.data(), s.indices.size());
  for (std::uint32_t a : m.adjacency()) EXPECT_NE(a, cpu::kNoNeighbour);
  // Three triangles on one edge (a fin): their edges on it form a ring of three; the
  // other edges belong to one triangle each.
  const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
  const std::uint32_t idx[] = {0, 1, 2, 0, 1, 3, 0, 1, 4};
  const std::uint32_t fin = m.addObject(p, 5, idx, 9);
  const cpu::OccluderObject& o = m.object(fin);
  for (std::uint32_t t = o.first_triangle; t < o.first_triangle + 3; ++t) {
    std::uint32_t e = t * 3 + 2, steps = 0;  // edge 2 is 0-1
    do {
      e = m.adjacency()[e];
      ++steps;
    } while (e != t * 3 + 2 && steps < 10);
    EXPECT_EQ(steps, 3u);
    EXPECT_EQ(m.adjacency()[t * 3], cpu::kNoNeighbour);
  }
  EXPECT_EQ(o.box.max.z, 1.0f);
}

TEST(OccluderMeshesTest, BadInputIsAClearError) {
  const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, NAN};
  const std::uint32_t idx[] = {0, 1, 2};
  OccluderMeshes m;
  test::expectError([&] { m.addObject(p, 3, idx, 2); }, ErrorCode::InvalidArgument,
                    {"object 0", "multiple of 3"});
  const std::uint32_t far_index[] = {0, 1, 7};
  test::expectError([&] { m.addObject(p, 3, far_index, 3); }, ErrorCode::InvalidArgument,
                    {"index 2 is 7", "3 vertices"});
  test::expectError([&] { m.addObject(p, 3, idx, 3); }, ErrorCode::InvalidArgument,
                    {"vertex 2", "finite"});
  test::expectError([&] { m.setInsideSolid(4, cpu::kNoOccluder); }, ErrorCode::InvalidArgument,
                    {"object 4"});
}

TEST(OcclusionBufferTest, BadUseIsAClearError) {
  const TestMesh b = test::box({{0, 0, 0}, {1, 1, 1}});
  const OccluderMeshes m = meshesOf({b});
  OcclusionBufferDesc bad;
  bad.projection.subpixel_bits = 40;
  test::expectError([&] { OcclusionBuffer x(m, bad); }, ErrorCode::InvalidArgument,
                    {"subpixel_bits 40"});
  bad = {};
  bad.threads = 1000;
  test::expectError([&] { OcclusionBuffer x(m, bad); }, ErrorCode::InvalidArgument,
                    {"1000 worker threads"});
  OcclusionBuffer buffer(m);
  test::expectError([&] { buffer.drawObject(0); }, ErrorCode::InvalidArgument,
                    {"between beginFrame() and endFrame()"});
  orThrow(buffer.beginFrame(test::randomCamera(
      1, 32, 32, DepthConvention::Standard, ClipDepthRange::NegativeOneToOne, DepthFormat::D32F)));
  test::expectError([&] { buffer.drawObject(3); }, ErrorCode::InvalidArgument,
                    {"object 3", "1 objects"});
  Camera broken;
  test::expectError([&] { orThrow(buffer.beginFrame(broken)); }, ErrorCode::InvalidArgument,
                    {"viewport"});
}

struct PropertyCase {
  DepthConvention convention;
  ClipDepthRange range;
  DepthFormat format;
  cpu::Resolution resolution;
  test::SnapMode snap;
  test::DepthModel model;
};

PropertyCase randomCase(std::mt19937& rng) {
  static const std::pair<DepthConvention, ClipDepthRange> conventions[] = {
      {DepthConvention::Standard, ClipDepthRange::NegativeOneToOne},
      {DepthConvention::Standard, ClipDepthRange::ZeroToOne},
      {DepthConvention::Reversed, ClipDepthRange::ZeroToOne}};
  const auto c = conventions[rng() % 3];
  const DepthFormat formats[] = {DepthFormat::D16, DepthFormat::D24, DepthFormat::D32F};
  const cpu::Resolution resolutions[] = {cpu::Resolution::Full, cpu::Resolution::Half,
                                         cpu::Resolution::Quarter};
  const test::SnapMode snaps[] = {test::SnapMode::Round, test::SnapMode::Truncate,
                                  test::SnapMode::Either};
  return {c.first,
          c.second,
          formats[rng() % 3],
          resolutions[rng() % 3],
          snaps[rng() % 3],
          rng() % 2 ? test::DepthModel::SnappedVertices : test::DepthModel::FloatPlane};
}

struct Tally {
  std::uint64_t nearer = 0;     // buffer keys nearer than the reference stores
  std::uint64_t covered = 0;    // pixels the buffer covers
  std::uint64_t reference = 0;  // pixels the reference covers
  std::string first;            // the first violation, described
};

enum class Motion : std::uint8_t {
  Still,        // the scene as it is
  Moved,        // moved, and drawn into the buffer with the transforms
  DrawnUnmoved  // moved for the reference, but drawn into the buffer without them
};

// Renders `scenes` random scenes with the buffer and the reference and compares.
Tally compareWithReference(int scenes, const OcclusionBufferDesc& base,
                           Motion motion = Motion::Still) {
  Tally tally;
  std::mt19937 rng(2024);
  for (int s = 0; s < scenes; ++s) {
    const PropertyCase c = randomCase(rng);
    const std::uint32_t w = 45 + std::uint32_t(rng() % 40), h = 33 + std::uint32_t(rng() % 30);
    const Camera cam =
        test::randomCamera(std::uint32_t(s) * 7 + 1, w, h, c.convention, c.range, c.format);
    std::vector<TestMesh> scene = test::randomScene(std::uint32_t(s) + 100);
    OcclusionBufferDesc desc = base;
    desc.resolution = c.resolution;
    std::vector<float> got;
    if (motion == Motion::Still) {
      got = render(meshesOf(scene), cam, desc);
    } else {
      test::MovedScene moved = test::moveScene(scene, rng);
      got = render(meshesOf(moved.local), cam, desc,
                   motion == Motion::Moved ? &moved.transforms : nullptr);
      scene = std::move(moved.placed);
    }
    test::SnappingRasterizer ref(cam, 4, c.snap, c.model);
    for (const TestMesh& m : scene) ref.draw(m);
    const float clear = clearKey(cam.depth);
    for (std::size_t i = 0; i < got.size(); ++i) {
      tally.covered += got[i] < clear;
      tally.reference += ref.keys()[i] < clear;
      if (got[i] < ref.keys()[i]) {
        if (tally.nearer++ == 0) {
          std::ostringstream out;
          out << "scene " << s << " pixel (" << i % w << ", " << i / w << ") of " << w << "x" << h
              << ", " << toString(c.convention) << " " << toString(c.format) << " "
              << cpu::toString(c.resolution) << ": buffer " << got[i] << " reference "
              << ref.keys()[i];
          tally.first = out.str();
        }
      }
    }
  }
  return tally;
}

TEST(OcclusionBufferTest, NeverNearerThanASnappingRasterizer) {
  const Tally t = compareWithReference(240, {});
  std::printf("covered %llu of %llu reference pixels\n", (unsigned long long)t.covered,
              (unsigned long long)t.reference);
  EXPECT_EQ(t.nearer, 0u) << t.first;
  // Meaningful: the buffer covers most of what the reference covers.
  EXPECT_GT(double(t.covered), 0.6 * double(t.reference)) << t.covered << " of " << t.reference;
}

TEST(OcclusionBufferTest, ExactCoverageCoversPixelsGlMayLeaveClear) {
  OcclusionBufferDesc desc;
  desc.unsafe_exact_coverage = true;
  const Tally t = compareWithReference(120, desc);
  EXPECT_GT(t.nearer, 0u) << "without the coverage slack no pixel differed";
  std::printf("exact coverage: %llu nearer: %s\n", (unsigned long long)t.nearer, t.first.c_str());
}

TEST(OcclusionBufferTest, ExactDepthIsNearerThanGlMayStore) {
  OcclusionBufferDesc desc;
  desc.unsafe_exact_depth = true;
  const Tally t = compareWithReference(120, desc);
  EXPECT_GT(t.nearer, 0u) << "without the depth slack no pixel differed";
  std::printf("exact depth: %llu nearer: %s\n", (unsigned long long)t.nearer, t.first.c_str());
}

// Moving objects, drawn with their transforms (OcclusionBuffer::drawObject(id,
// transform)): their vertices placed as the application draws them, every rule kept,
// in both representations, lazily and with a worker. Drawn without their transforms
// (where their own coordinates put them) the buffer holds keys where the reference has
// none or farther ones: the placement is what makes it conservative.
TEST(OcclusionBufferTest, MovedObjectsNeverNearerThanASnappingRasterizer) {
  for (cpu::Representation r : {cpu::Representation::PerPixel, cpu::Representation::Masked}) {
    for (std::uint32_t threads : {0u, 1u}) {
      OcclusionBufferDesc desc;
      desc.representation = r;
      desc.threads = threads;
      const Tally t = compareWithReference(threads ? 40 : 160, desc, Motion::Moved);
      std::printf("moved, %s, %u workers: covered %llu of %llu reference pixels\n",
                  cpu::toString(r), threads, (unsigned long long)t.covered,
                  (unsigned long long)t.reference);
      EXPECT_EQ(t.nearer, 0u) << cpu::toString(r) << ", " << threads << " workers: " << t.first;
      EXPECT_GT(double(t.covered), 0.4 * double(t.reference)) << t.covered << " of " << t.reference;
    }
  }
  const Tally unmoved = compareWithReference(40, {}, Motion::DrawnUnmoved);
  EXPECT_GT(unmoved.nearer, 0u) << "drawn where their own coordinates put them, no pixel differed";
}

// A moving wall hides what is behind it where the frame draws it: a quad modelled in its
// own y-z plane (edge-on to an eye on the z axis), turned a quarter about y to face the
// eye and moved between the eye and a box. Drawn with that transform the box's pixels
// all hold keys in front of the box; drawn unmoved (edge-on) the box's rectangle stays
// clear.
TEST(OcclusionBufferTest, AMovedWallHidesTheBoxBehindIt) {
  const float quad[] = {0, -2, -2, 0, 2, -2, 0, 2, 2, 0, -2, 2};
  const std::uint32_t indices[] = {0, 1, 2, 0, 2, 3};
  OccluderMeshes meshes;
  const std::uint32_t wall = meshes.addObject(quad, 4, indices, 6);
  Camera cam;
  cam.width = 64;
  cam.height = 64;
  for (DepthConvention convention : {DepthConvention::Standard, DepthConvention::Reversed}) {
    cam.depth = {convention,
                 convention == DepthConvention::Reversed ? ClipDepthRange::ZeroToOne
                                                         : ClipDepthRange::NegativeOneToOne,
                 DepthFormat::D24};
    cam.view_projection = multiply(perspective(1.0, 1.0, 0.5, 100, cam.depth),
                                   lookAt({0, 0, 10}, {0, 0, 0}, {0, 1, 0}));
    cam.render_origin = {0, 0, 10};
    const BoxProjection target = Projector(cam).project({{-0.5f, -0.5f, -6}, {0.5f, 0.5f, -5}});
    ASSERT_EQ(target.cls, ProjectionClass::Inside);
    cpu::ObjectTransform turned;  // a quarter turn about y: local x becomes -z
    const double r[9] = {0, 0, -1, 0, 1, 0, 1, 0, 0};
    std::copy(r, r + 9, turned.rotation);
    turned.translation = {0.25, -0.1, 2};
    for (bool moved : {true, false}) {
      OcclusionBuffer buffer(meshes);
      orThrow(buffer.beginFrame(cam));
      if (moved) {
        buffer.drawObject(wall, turned);
      } else {
        buffer.drawObject(wall);
      }
      AreaRequest request;
      request.rect = target.rect;
      AreaAnswer answer;
      buffer.submit(&request, 1, &answer);
      orThrow(buffer.endFrame());
      if (moved) {
        EXPECT_EQ(answer.depth.free_pixels, 0u) << toString(convention);
        EXPECT_LT(answer.depth.max_key, target.occlusionThreshold()) << toString(convention);
        EXPECT_EQ(buffer.stats().objects_moved, 1u);
      } else {
        EXPECT_EQ(answer.depth.free_pixels, std::uint32_t(target.rect.area()))
            << toString(convention);
      }
    }
  }
  OcclusionBuffer buffer(meshes);
  orThrow(buffer.beginFrame(cam));
  cpu::ObjectTransform broken;
  broken.translation.y = NAN;
  test::expectError([&] { buffer.drawObject(wall, broken); }, ErrorCode::InvalidArgument,
                    {"object 0", "not finite"});
}

// The masked representation (a mask and two keys per 8 x 4 block) under the same
// reference: never nearer, at every resolution, lazily and with a worker (whose order of
// triangles differs, and a block's keys depend on the order they land in).
TEST(OcclusionBufferTest, MaskedNeverNearerThanASnappingRasterizer) {
  for (std::uint32_t threads : {0u, 1u}) {
    OcclusionBufferDesc desc;
    desc.representation = cpu::Representation::Masked;
    desc.threads = threads;
    const Tally t = compareWithReference(threads ? 60 : 240, desc);
    std::printf("masked, %u workers: covered %llu of %llu reference pixels\n", threads,
                (unsigned long long)t.covered, (unsigned long long)t.reference);
    EXPECT_EQ(t.nearer, 0u) << t.first;
    EXPECT_GT(double(t.covered), 0.4 * double(t.reference)) << t.covered << " of " << t.reference;
  }
}

// Each rule broken in the masked representation shows against the reference: the two
// rules it shares with the per-pixel buffer, and its own merge rule.
TEST(OcclusionBufferTest, MaskedBreakingARuleIsNearerThanGlMayStore) {
  struct Broken {
    const char* name;
    bool OcclusionBufferDesc::*flag;
  };
  for (const Broken b : {Broken{"exact coverage", &OcclusionBufferDesc::unsafe_exact_coverage},
                         Broken{"exact depth", &OcclusionBufferDesc::unsafe_exact_depth},
                         Broken{"nearer merge", &OcclusionBufferDesc::unsafe_masked_merge}}) {
    OcclusionBufferDesc desc;
    desc.representation = cpu::Representation::Masked;
    desc.*b.flag = true;
    const Tally t = compareWithReference(120, desc);
    EXPECT_GT(t.nearer, 0u) << b.name << ": no pixel differed";
    std::printf("masked, %s: %llu nearer: %s\n", b.name, (unsigned long long)t.nearer,
                t.first.c_str());
  }
}

// Every masked key is at or behind the per-pixel buffer's key there (a block holds the
// farthest bound of what landed in it), and the masked buffer still covers most of it.
TEST(OcclusionBufferTest, MaskedKeysAreAtOrBehindPerPixelKeys) {
  std::mt19937 rng(5);
  std::uint64_t per_pixel_covered = 0, masked_covered = 0;
  for (int s = 0; s < 60; ++s) {
    const PropertyCase c = randomCase(rng);
    const Camera cam = test::randomCamera(std::uint32_t(s) + 17, 67 + std::uint32_t(rng() % 30), 51,
                                          c.convention, c.range, c.format);
    const OccluderMeshes meshes = meshesOf(test::randomScene(std::uint32_t(s) + 300));
    OcclusionBufferDesc desc;
    desc.resolution = c.resolution;
    const std::vector<float> per_pixel = render(meshes, cam, desc);
    desc.representation = cpu::Representation::Masked;
    const std::vector<float> masked = render(meshes, cam, desc);
    const float clear = clearKey(cam.depth);
    for (std::size_t i = 0; i < masked.size(); ++i) {
      // Both are float bounds evaluated from rows stepped from different starts (blocks
      // of 8 x 8 and 8 x 4): equal up to a few roundings.
      ASSERT_GE(masked[i], per_pixel[i] - 4e-7f) << "scene " << s << " pixel " << i;
      per_pixel_covered += per_pixel[i] < clear;
      masked_covered += masked[i] < clear;
    }
  }
  std::printf("masked covers %llu of the per-pixel buffer's %llu pixels\n",
              (unsigned long long)masked_covered, (unsigned long long)per_pixel_covered);
  EXPECT_GT(double(masked_covered), 0.7 * double(per_pixel_covered));
}

// Occluder selection leaves objects out (never a key nearer than with every object) and
// keeps each frame's selected triangles within the budget.
TEST(OcclusionBufferTest, SelectionKeepsTheBudgetAndOnlyLeavesKeysFarther) {
  std::mt19937 rng(9);
  std::uint64_t left_out = 0, farther = 0;
  for (int s = 0; s < 30; ++s) {
    const PropertyCase c = randomCase(rng);
    const Camera cam =
        test::randomCamera(std::uint32_t(s) + 23, 70, 52, c.convention, c.range, c.format);
    const OccluderMeshes meshes = meshesOf(test::randomScene(std::uint32_t(s) + 500));
    for (cpu::Representation rep : {cpu::Representation::PerPixel, cpu::Representation::Masked}) {
      OcclusionBufferDesc desc;
      desc.resolution = c.resolution;
      desc.representation = rep;
      const std::vector<float> all = render(meshes, cam, desc);
      desc.min_pixels_per_triangle = 4;
      desc.triangle_budget = 40;
      OcclusionBuffer buffer(meshes, desc);
      orThrow(buffer.beginFrame(cam));
      for (std::uint32_t i = 0; i < meshes.objectCount(); ++i) buffer.drawObject(i);
      std::vector<float> keys(all.size());
      buffer.readKeys({0, 0, std::int32_t(cam.width), std::int32_t(cam.height)}, keys.data());
      orThrow(buffer.endFrame());
      EXPECT_LE(buffer.stats().triangles_selected, 40u) << "scene " << s;
      EXPECT_LE(buffer.stats().triangles_set_up, buffer.stats().triangles_selected);
      left_out += buffer.stats().objects_unselected;
      for (std::size_t i = 0; i < keys.size(); ++i) {
        if (rep == cpu::Representation::PerPixel) {
          ASSERT_GE(keys[i], all[i]) << "scene " << s << " pixel " << i;
        }
        farther += keys[i] > all[i];
      }
    }
  }
  EXPECT_GT(left_out, 0u);
  EXPECT_GT(farther, 0u);
}

TEST(OcclusionBufferTest, EveryKernelWritesTheSameBuffer) {
  for (cpu::Isa isa : {cpu::Isa::Sse41, cpu::Isa::Avx2}) {
    for (cpu::Representation rep : {cpu::Representation::PerPixel, cpu::Representation::Masked}) {
      if (!cpu::isaSupported(isa)) {
        std::printf("skipping %s: this CPU does not run it\n", cpu::toString(isa));
        continue;
      }
      std::mt19937 rng(7);
      std::size_t compared = 0;
      for (int s = 0; s < 60; ++s) {
        const PropertyCase c = randomCase(rng);
        const Camera cam = test::randomCamera(std::uint32_t(s) + 3, 61 + std::uint32_t(rng() % 30),
                                              47, c.convention, c.range, c.format);
        const OccluderMeshes meshes = meshesOf(test::randomScene(std::uint32_t(s)));
        OcclusionBufferDesc desc;
        desc.resolution = c.resolution;
        desc.representation = rep;
        desc.isa = cpu::Isa::Scalar;
        const std::vector<float> scalar = render(meshes, cam, desc);
        desc.isa = isa;
        const std::vector<float> simd = render(meshes, cam, desc);
        ASSERT_EQ(scalar.size(), simd.size());
        for (std::size_t i = 0; i < scalar.size(); ++i) {
          ASSERT_EQ(scalar[i], simd[i]) << cpu::toString(isa) << " " << cpu::toString(rep)
                                        << " scene " << s << " pixel " << i;
        }
        compared += scalar.size();
      }
      EXPECT_GT(compared, 0u);
    }
  }
}

TEST(OcclusionBufferTest, WorkerThreadsWriteTheSameBuffer) {
  // One, two and three threads, one buffer over several frames (tiles left from the
  // frame before must be cleared), a request between draws: every key as the lazy
  // caller's.
  std::mt19937 rng(11);
  for (std::uint32_t threads : {1u, 2u, 3u}) {
    std::size_t covered = 0;  // keys in front of the clear one (the comparison is not vacuous)
    for (int s = 0; s < 8; ++s) {
      const OccluderMeshes meshes = meshesOf(test::randomScene(std::uint32_t(s) + 40));
      OcclusionBufferDesc desc;
      desc.resolution = randomCase(rng).resolution;
      desc.threads = threads;
      OcclusionBuffer buffer(meshes, desc);
      for (std::uint32_t frame = 0; frame < 3; ++frame) {
        const PropertyCase c = randomCase(rng);
        const Camera cam = test::randomCamera(std::uint32_t(s) * 3 + frame + 5, 70, 52,
                                              c.convention, c.range, c.format);
        OcclusionBufferDesc lazy = desc;
        lazy.threads = 0;
        const std::vector<float> expected = render(meshes, cam, lazy);
        orThrow(buffer.beginFrame(cam));
        const std::uint32_t half = std::uint32_t(meshes.objectCount() / 2);
        for (std::uint32_t i = 0; i < half; ++i) buffer.drawObject(i);
        const PixelRect corner{0, 0, 20, 20};
        AreaDepth a;
        buffer.summarize(&corner, 1, &a);
        for (std::uint32_t i = half; i < meshes.objectCount(); ++i) buffer.drawObject(i);
        std::vector<float> keys(expected.size());
        buffer.readKeys({0, 0, std::int32_t(cam.width), std::int32_t(cam.height)}, keys.data());
        orThrow(buffer.endFrame());
        for (std::size_t i = 0; i < keys.size(); ++i) {
          ASSERT_EQ(keys[i], expected[i])
              << threads << " workers, scene " << s << " frame " << frame << " pixel " << i;
          const float clear = c.convention == DepthConvention::Reversed ? 0.0f : 1.0f;
          covered += keys[i] != clear;
        }
      }
      EXPECT_EQ(buffer.stats().objects_set_up,
                buffer.stats().objects_drawn - buffer.stats().objects_skipped);
    }
    EXPECT_GT(covered, 0u);
  }
}

TEST(OcclusionBufferTest, CoarseResolutionsHoldTheFarthestKeyOfTheirBlock) {
  // A wall facing the camera, seen at full, half and quarter resolution: a covered
  // block's key is at or behind every full-resolution key in it, and blocks at the
  // wall's edge are left clear where any of their pixels is.
  const TestMesh wall = test::heightField(-3, -3, 6, 6, 0, 0.3, 5);
  const OccluderMeshes meshes = meshesOf({wall});
  Camera cam = test::randomCamera(11, 64, 48, DepthConvention::Standard,
                                  ClipDepthRange::NegativeOneToOne, DepthFormat::D32F);
  cam.view_projection = multiply(perspective(0.9, 64.0 / 48, 0.5, 60, cam.depth),
                                 lookAt({0.3, 8, 0.2}, {0, 0, 0}, {0, 0, 1}));
  OcclusionBufferDesc desc;
  const std::vector<float> full = render(meshes, cam, desc);
  for (cpu::Resolution r : {cpu::Resolution::Half, cpu::Resolution::Quarter}) {
    desc.resolution = r;
    const std::vector<float> coarse = render(meshes, cam, desc);
    std::size_t covered = 0;
    for (std::size_t i = 0; i < full.size(); ++i) {
      const std::size_t x = i % 64, y = i / 64;
      // Every pixel of a covered block: its full-resolution key is at most the block's.
      if (coarse[i] < 1.0f) {
        ++covered;
        // (Both are bounds computed in float from different sample points: equal up to
        // a few roundings where the plane is flat.)
        EXPECT_GE(coarse[i], full[i] - 4e-7f) << cpu::toString(r) << " pixel " << x << "," << y;
      }
    }
    EXPECT_GT(covered, full.size() / 4) << cpu::toString(r);
  }
}

TEST(OcclusionBufferTest, WorksLazilyTileByTile) {
  // Two objects far apart on screen: asking about one tile sets up only the object that
  // may cover it, and rasterises only the tiles asked about.
  const TestMesh left = test::box({{-15, -1, -1}, {-13, 1, 1}});  // pixels 8..24
  const TestMesh right = test::box({{13, -1, -1}, {15, 1, 1}});   // pixels 232..248
  const OccluderMeshes meshes = meshesOf({left, right});
  Camera cam;
  cam.width = 256;
  cam.height = 64;
  cam.depth = {DepthConvention::Standard, ClipDepthRange::NegativeOneToOne, DepthFormat::D32F};
  cam.view_projection = multiply(orthographic(-16, 16, -4, 4, 1, 100, cam.depth),
                                 lookAt({0, 0, 20}, {0, 0, 0}, {0, 1, 0}));  // 8 pixels a unit
  OcclusionBuffer buffer(meshes);
  orThrow(buffer.beginFrame(cam));
  buffer.drawObject(0);
  buffer.drawObject(1);
  EXPECT_EQ(buffer.stats().objects_set_up, 0u);
  const PixelRect tile{0, 0, 32, 32};
  AreaDepth a;
  buffer.summarize(&tile, 1, &a);
  EXPECT_EQ(buffer.stats().objects_set_up, 1u);
  EXPECT_EQ(buffer.stats().tiles_rasterized, 1u);
  EXPECT_EQ(buffer.stats().triangles_set_up, 12u);
  const PixelRect middle{112, 16, 144, 48};  // between the two boxes
  std::uint32_t n = 0;
  buffer.countAtOrBeyond(&middle, 1, 0.5f, &n);
  EXPECT_EQ(n, 32u * 32u);
  EXPECT_EQ(buffer.stats().objects_set_up, 1u);
  // The whole left box is covered near its centre, at a key in front of the clear one.
  const PixelRect centre{14, 30, 18, 34};
  buffer.summarize(&centre, 1, &a);
  EXPECT_LT(a.max_key, 1.0f);
  EXPECT_EQ(a.free_pixels, 0u);
  orThrow(buffer.endFrame());
}

TEST(OcclusionBufferTest, MultisampledPixelsAreCoveredOnlyWhenTheirWholeSquareIs) {
  // A box whose right edge lands at window x = 9.8: the centre of pixel 9 lies 0.3 pixel
  // inside it, far beyond the snapping slack, but a sample at x offset +0.375 (GL's
  // standard 4x pattern) lies outside. Single-sampled, pixel 9 is covered; multisampled,
  // an object behind it shows through that sample, so the buffer must leave it clear
  // (`logrid walk --reader cpu --samples 4` relies on it). Pixels 5 to 8 are covered
  // either way.
  const TestMesh wall = test::box({{-15.5f, -1, -1}, {-14.775f, 1, 1}});  // x 4 .. 9.8
  const OccluderMeshes meshes = meshesOf({wall});
  for (bool multisample : {false, true}) {
    Camera cam;
    cam.width = 256;
    cam.height = 64;
    cam.depth = {DepthConvention::Standard, ClipDepthRange::NegativeOneToOne, DepthFormat::D32F};
    cam.view_projection = multiply(orthographic(-16, 16, -4, 4, 1, 100, cam.depth),
                                   lookAt({0, 0, 20}, {0, 0, 0}, {0, 1, 0}));  // 8 px a unit
    cam.multisample = multisample;
    OcclusionBuffer buffer(meshes);
    orThrow(buffer.beginFrame(cam));
    buffer.drawObject(0);
    float keys[5];
    buffer.readKeys({5, 32, 10, 33}, keys);
    orThrow(buffer.endFrame());
    for (int x = 5; x < 9; ++x) {
      EXPECT_LT(keys[x - 5], 1.0f) << "pixel " << x << ", multisample " << multisample;
    }
    if (multisample) {
      EXPECT_EQ(keys[4], 1.0f) << "pixel 9 of a multisampled buffer claimed covered";
    } else {
      EXPECT_LT(keys[4], 1.0f) << "pixel 9 single-sampled";
    }
  }
}

TEST(OcclusionBufferTest, ModelsInsideAnObjectNeedTheObjectBeyondTheNearPlane) {
  // A model (a small box) inside a big one, with the big one as its fallback. Seen from
  // afar the model is used; with the eye inside the object the fallback is.
  const TestMesh outer = test::box({{-2, -2, -2}, {2, 2, 2}});
  const TestMesh inner = test::box({{-1, -1, -1}, {1, 1, 1}});
  OccluderMeshes meshes;
  const Aabb outer_box{{-2, -2, -2}, {2, 2, 2}};
  const std::uint32_t model = meshes.addObject(inner.positions.data(), 8, inner.indices.data(),
                                               inner.indices.size(), &outer_box);
  const std::uint32_t full =
      meshes.addObject(outer.positions.data(), 8, outer.indices.data(), outer.indices.size());
  meshes.setInsideSolid(model, full);
  OcclusionBuffer buffer(meshes);
  Camera cam;
  cam.width = 64;
  cam.height = 64;
  cam.depth = {DepthConvention::Standard, ClipDepthRange::NegativeOneToOne, DepthFormat::D32F};
  for (double distance : {10.0, 1.0}) {
    cam.view_projection = multiply(perspective(1.0, 1.0, 0.1, 100, cam.depth),
                                   lookAt({0, 0, distance}, {0, 0, 0}, {0, 1, 0}));
    const auto before = buffer.stats();
    orThrow(buffer.beginFrame(cam));
    buffer.drawObject(model);
    std::vector<float> keys(64 * 64);
    buffer.readKeys({0, 0, 64, 64}, keys.data());
    orThrow(buffer.endFrame());
    EXPECT_EQ(buffer.stats().objects_fallback - before.objects_fallback, distance < 2 ? 1u : 0u);
    EXPECT_EQ(buffer.stats().objects_set_up - before.objects_set_up, 1u);
  }
}

}  // namespace
}  // namespace logrid
