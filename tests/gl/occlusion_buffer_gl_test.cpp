// The CPU occlusion buffer against GL on rendered frames: random scenes of closed,
// open, seamed, sliver and soup meshes (tests/support/occluder_scenes.hpp) drawn by the
// mesh renderer, in every depth format and convention, and the same objects drawn into
// the buffer at every resolution. Per pixel, the buffer never holds a key nearer than GL
// stored (read back through glReadPixels), so it never covers a pixel GL left clear.
// With a conservative rule switched off, GL shows a pixel where it is nearer.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <sstream>

#include "gl_test_context.hpp"
#include "logrid/cpu/occlusion_buffer.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/gl/mesh_renderer.hpp"
#include "occluder_scenes.hpp"

namespace logrid {
namespace {

using test::TestMesh;

gl::RenderMesh renderMesh(const std::vector<TestMesh>& scene) {
  gl::RenderMesh mesh;
  for (const TestMesh& m : scene) {
    gl::RenderMesh::Draw d;
    d.first_index = std::uint32_t(mesh.indices32.size());
    d.index_count = std::uint32_t(m.indices.size());
    d.base_vertex = std::int32_t(mesh.positions.size() / 3);
    d.color = 0xFF808080u;
    mesh.positions.insert(mesh.positions.end(), m.positions.begin(), m.positions.end());
    mesh.indices32.insert(mesh.indices32.end(), m.indices.begin(), m.indices.end());
    mesh.draws.push_back(d);
  }
  return mesh;
}

struct Comparison {
  std::uint64_t nearer = 0;      // buffer keys nearer than GL's
  std::uint64_t covered = 0;     // pixels the buffer covers
  std::uint64_t gl_covered = 0;  // pixels GL covers
  std::string first;
};

// How the objects are drawn: as they are, or moved (test::moveScene: each in its own
// coordinates, turned about its centre by a transform, as the renderer draws movers),
// and then either into the buffer with the same transforms or, to show what the
// transforms do, without them. MovedFar: moved, their own origin 1e4 from them on each
// axis (test::moveScene's `far`), and the scene and the eye 1e4 from the world's origin.
enum class Motion : std::uint8_t { Still, Moved, DrawnUnmoved, MovedFar };
constexpr double kFar = 1e4;

// Renders random scenes in GL and in the buffer and compares every pixel.
Comparison compare(DepthFormat format, DepthConvention convention, cpu::Resolution resolution,
                   const cpu::OcclusionBufferDesc& base, int scenes,
                   Motion motion = Motion::Still) {
  Comparison out;
  std::mt19937 rng(77);
  for (int s = 0; s < scenes; ++s) {
    const std::uint32_t w = 96 + std::uint32_t(s % 5) * 7, h = 72 + std::uint32_t(s % 3) * 5;
    const ClipDepthRange range = convention == DepthConvention::Reversed || s % 2
                                     ? ClipDepthRange::ZeroToOne
                                     : ClipDepthRange::NegativeOneToOne;
    Camera cam = test::randomCamera(std::uint32_t(s) * 13 + 5, w, h, convention, range, format);
    std::vector<TestMesh> scene = test::randomScene(std::uint32_t(s) + 900);
    std::vector<cpu::ObjectTransform> transforms;
    if (motion != Motion::Still) {
      test::MovedScene moved = test::moveScene(scene, rng, motion == Motion::MovedFar ? kFar : 0);
      scene = std::move(moved.local);
      transforms = std::move(moved.transforms);
    }
    if (motion == Motion::MovedFar) {
      for (cpu::ObjectTransform& t : transforms) {
        t.translation = {t.translation.x + kFar, t.translation.y + kFar, t.translation.z + kFar};
      }
      cam.view_projection = multiply(cam.view_projection, translation({-kFar, -kFar, -kFar}));
      cam.render_origin = {cam.render_origin.x + kFar, cam.render_origin.y + kFar,
                           cam.render_origin.z + kFar};
    }
    gl::Framebuffer fb({w, h, cam.depth, false});
    fb.bind();
    const float clear[4] = {0, 0, 0, 1};
    fb.clear(clear);
    gl::MeshRenderer renderer(renderMesh(scene));
    for (ObjectId id = 0; id < transforms.size(); ++id) {
      gl::ObjectTransform t;  // as the frame runner hands a mover's to the renderer
      for (int k = 0; k < 9; ++k) t.rotation[k] = static_cast<float>(transforms[id].rotation[k]);
      t.translation = transforms[id].translation;
      renderer.setTransform(id, t);
    }
    renderer.begin(gl::Pass::DepthOnly, cam);
    for (ObjectId id = 0; id < renderer.objectCount(); ++id) renderer.draw(id);
    renderer.end();
    const std::vector<float> depth = fb.readDepth();

    cpu::OccluderMeshes meshes;
    for (const TestMesh& m : scene) {
      meshes.addObject(m.positions.data(), m.positions.size() / 3, m.indices.data(),
                       m.indices.size());
    }
    cpu::OcclusionBufferDesc desc = base;
    desc.resolution = resolution;
    cpu::OcclusionBuffer buffer(meshes, desc);
    orThrow(buffer.beginFrame(cam));
    for (std::uint32_t i = 0; i < meshes.objectCount(); ++i) {
      if (motion == Motion::Moved || motion == Motion::MovedFar) {
        buffer.drawObject(i, transforms[i]);
      } else {
        buffer.drawObject(i);
      }
    }
    std::vector<float> keys(std::size_t(w) * h);
    buffer.readKeys({0, 0, std::int32_t(w), std::int32_t(h)}, keys.data());
    orThrow(buffer.endFrame());

    const float clear_key = clearKey(cam.depth);
    for (std::size_t i = 0; i < keys.size(); ++i) {
      const float gl_key = depthKey(convention, depth[i]);
      out.covered += keys[i] < clear_key;
      out.gl_covered += gl_key < clear_key;
      if (keys[i] < gl_key && out.nearer++ == 0) {
        std::ostringstream m;
        m.precision(9);
        m << "scene " << s << " pixel (" << i % w << ", " << i / w << "): buffer " << keys[i]
          << ", GL " << gl_key;
        out.first = m.str();
      }
    }
  }
  return out;
}

struct Case {
  DepthFormat format;
  DepthConvention convention;
  cpu::Resolution resolution;
  cpu::Representation representation;
};

class OcclusionBufferGlTest : public testing::TestWithParam<Case> {};

TEST_P(OcclusionBufferGlTest, NeverNearerThanGl) {
  LOGRID_REQUIRE_GL();
  const Case c = GetParam();
  cpu::OcclusionBufferDesc desc;
  desc.representation = c.representation;
  // The D24 cases on two threads (binned: the masked blocks land in draw order, not in
  // the lazy buffer's order of requests), the others lazily.
  desc.threads = c.format == DepthFormat::D24 ? 2 : 0;
  const Comparison r = compare(c.format, c.convention, c.resolution, desc, 24);
  EXPECT_EQ(r.nearer, 0u) << r.first;
  const double share = double(r.covered) / double(std::max<std::uint64_t>(1, r.gl_covered));
  std::printf("[ cpu ] %s %s %s %s, %u threads: covers %.1f%% of GL's pixels\n", toString(c.format),
              toString(c.convention), cpu::toString(c.resolution), cpu::toString(c.representation),
              desc.threads, 100 * share);
  // Meaningful: the buffer covers a good part of what GL covers.
  EXPECT_GT(share, c.resolution == cpu::Resolution::Full ? 0.8 : 0.3);
}

std::string caseName(const testing::TestParamInfo<Case>& p) {
  return std::string("d") + toString(p.param.format) + "_" + toString(p.param.convention) + "_" +
         cpu::toString(p.param.resolution) +
         (p.param.representation == cpu::Representation::Masked ? "_masked" : "");
}

std::vector<Case> cases() {
  std::vector<Case> out;
  for (DepthFormat f : {DepthFormat::D16, DepthFormat::D24, DepthFormat::D32F}) {
    for (DepthConvention c : {DepthConvention::Standard, DepthConvention::Reversed}) {
      for (cpu::Resolution r :
           {cpu::Resolution::Full, cpu::Resolution::Half, cpu::Resolution::Quarter}) {
        for (cpu::Representation m : {cpu::Representation::PerPixel, cpu::Representation::Masked}) {
          out.push_back({f, c, r, m});
        }
      }
    }
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(AllFormats, OcclusionBufferGlTest, testing::ValuesIn(cases()), caseName);

// The movers placed by `motion` in every format and convention, per pixel (full
// resolution) and masked (half): never nearer than GL, and covering at least
// `least_full_share` of GL's pixels at full resolution (0.3 at half).
void checkMoversInEveryFormat(Motion motion, const char* label, double least_full_share) {
  for (DepthFormat f : {DepthFormat::D16, DepthFormat::D24, DepthFormat::D32F}) {
    for (DepthConvention c : {DepthConvention::Standard, DepthConvention::Reversed}) {
      for (cpu::Representation m : {cpu::Representation::PerPixel, cpu::Representation::Masked}) {
        cpu::OcclusionBufferDesc desc;
        desc.representation = m;
        const cpu::Resolution r =
            m == cpu::Representation::Masked ? cpu::Resolution::Half : cpu::Resolution::Full;
        const Comparison got = compare(f, c, r, desc, 12, motion);
        EXPECT_EQ(got.nearer, 0u) << label << " " << toString(f) << " " << toString(c) << " "
                                  << cpu::toString(m) << ": " << got.first;
        const double share =
            double(got.covered) / double(std::max<std::uint64_t>(1, got.gl_covered));
        std::printf("[ cpu ] %s %s %s %s %s: covers %.1f%% of GL's pixels\n", label, toString(f),
                    toString(c), cpu::toString(r), cpu::toString(m), 100 * share);
        EXPECT_GT(share, r == cpu::Resolution::Full ? least_full_share : 0.3);
      }
    }
  }
}

// Moving objects drawn by the renderer with their transforms (its float rotation and
// offset) and into the buffer with the same transforms: never nearer than GL, in every
// format and convention, per pixel and masked. Drawn into the buffer without them, the
// buffer is nearer than GL somewhere.
TEST(OcclusionBufferGlMovers, NeverNearerThanGl) {
  LOGRID_REQUIRE_GL();
  checkMoversInEveryFormat(Motion::Moved, "movers", 0.8);
  const Comparison unmoved = compare(DepthFormat::D24, DepthConvention::Standard,
                                     cpu::Resolution::Full, {}, 12, Motion::DrawnUnmoved);
  EXPECT_GT(unmoved.nearer, 0u) << "drawn without their transforms, never nearer than GL";
}

// The pad of a moving object's vertices (occlusion_buffer.hpp, "Moving objects": 16 u
// max(1, max|R|) |p|_1) against GL's float rotation and offset where they matter: each
// object's own origin 1e4 from it, so that |p|_1 is about 3e4, with rotations mirrored,
// scaled by 3.7 and singular, the eye 1e4 from the world's origin. Never nearer than
// GL; with the pad left out (placementPad returning 0) the buffer is nearer than GL in
// every format and convention, which the recentred objects above do not show.
TEST(OcclusionBufferGlMovers, NeverNearerThanGlFarFromTheirOwnOrigin) {
  LOGRID_REQUIRE_GL();
  checkMoversInEveryFormat(Motion::MovedFar, "movers far from their origin", 0.6);
}

// Each conservative rule is needed on GL too: without the coverage slack the buffer
// covers pixels GL leaves clear (edges through pixel centres after snapping), and
// without the depth slack it holds keys nearer than GL stores (D24 rounds and the
// snapped plane differs).
TEST(OcclusionBufferGlRules, BreakingARuleShowsOnGl) {
  LOGRID_REQUIRE_GL();
  cpu::OcclusionBufferDesc exact_coverage;
  exact_coverage.unsafe_exact_coverage = true;
  const Comparison a = compare(DepthFormat::D32F, DepthConvention::Standard, cpu::Resolution::Full,
                               exact_coverage, 24);
  EXPECT_GT(a.nearer, 0u) << "exact coverage was never nearer than GL";
  cpu::OcclusionBufferDesc exact_depth;
  exact_depth.unsafe_exact_depth = true;
  const Comparison b =
      compare(DepthFormat::D24, DepthConvention::Standard, cpu::Resolution::Full, exact_depth, 24);
  EXPECT_GT(b.nearer, 0u) << "exact depth was never nearer than GL";
  std::printf("[ cpu ] exact coverage: %llu pixels nearer (%s); exact depth: %llu (%s)\n",
              (unsigned long long)a.nearer, a.first.c_str(), (unsigned long long)b.nearer,
              b.first.c_str());
}

// The same in the masked representation, and its own rule: a triangle joining a block's
// layer must leave the layer's key at the farther of the two keys (taking the nearer
// gives the layer's other pixels keys nearer than GL's).
TEST(OcclusionBufferGlRules, BreakingAMaskedRuleShowsOnGl) {
  LOGRID_REQUIRE_GL();
  struct Broken {
    const char* name;
    bool cpu::OcclusionBufferDesc::*flag;
    DepthFormat format;
  };
  for (const Broken b :
       {Broken{"exact coverage", &cpu::OcclusionBufferDesc::unsafe_exact_coverage,
               DepthFormat::D32F},
        Broken{"exact depth", &cpu::OcclusionBufferDesc::unsafe_exact_depth, DepthFormat::D24},
        Broken{"nearer merge", &cpu::OcclusionBufferDesc::unsafe_masked_merge, DepthFormat::D24}}) {
    cpu::OcclusionBufferDesc desc;
    desc.representation = cpu::Representation::Masked;
    desc.*b.flag = true;
    const Comparison c =
        compare(b.format, DepthConvention::Standard, cpu::Resolution::Full, desc, 24);
    EXPECT_GT(c.nearer, 0u) << "masked, " << b.name << ": never nearer than GL";
    std::printf("[ cpu ] masked, %s: %llu pixels nearer (%s)\n", b.name,
                (unsigned long long)c.nearer, c.first.c_str());
  }
}

}  // namespace
}  // namespace logrid
