// The result forms (logrid/error.hpp): the codes and messages of the throwing forms,
// without an exception; a depth source's error ends the batch and the frame that met it,
// and the next frame culls as if it had not happened; a refused input leaves nothing
// half-done. (tests/install/consumer builds the same calls with -fno-exceptions.)
#include <gtest/gtest.h>

#include <limits>
#include <set>
#include <string>
#include <vector>

#include "box_world.hpp"
#include "logrid/config.hpp"
#include "logrid/cpu/occluder_mesh.hpp"
#include "logrid/culler.hpp"
#include "logrid/error.hpp"

namespace logrid {
namespace {

// The message the throwing form throws for the same call.
template <typename F>
std::string thrown(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

TEST(ResultForms, CreateRefusesWhatTheConstructorRefusesWithTheSameMessage) {
  CullerDesc bad;
  bad.tile_size = 0;
  const Result<Culler> made = Culler::create(bad);
  ASSERT_FALSE(made.ok());
  EXPECT_EQ(made.status().code(), ErrorCode::InvalidArgument);
  EXPECT_NE(made.status().message().find("tile size 0"), std::string::npos);
  EXPECT_EQ(made.status().message(), thrown([&] { Culler c(bad); }));
  EXPECT_TRUE(Culler::create({}).ok());
}

TEST(ResultForms, MatrixHelpersAndFilesReportTheirErrors) {
  const Result<Mat4d> look = tryLookAt({0, 0, 0}, {0, 0, 0}, {0, 1, 0});
  ASSERT_FALSE(look.ok());
  EXPECT_EQ(look.status().code(), ErrorCode::InvalidArgument);
  EXPECT_EQ(look.status().message(), thrown([] { lookAt({0, 0, 0}, {0, 0, 0}, {0, 1, 0}); }));
  EXPECT_FALSE(tryPerspective(1.0, 1.0, 0.0, 10.0, {}).ok());
  EXPECT_FALSE(tryOrthographic(1, -1, -1, 1, 0.1, 10, {}).ok());
  EXPECT_TRUE(tryPerspective(1.0, 1.0, 0.1, 10.0, {}).ok());

  // Malformed JSON, a wrong format, a bad value, an unreadable file: each as the throwing
  // form words it.
  for (const std::string text : {"{\"format\": ", "{\"format\": \"other\", \"version\": 1}",
                                 "{\"format\": \"logrid-config\", \"version\": 1, \"culler\": "
                                 "{\"method\": \"log-zfar\", \"tile_size\": 0}}"}) {
    const Result<CullerConfig> parsed = tryParseCullerConfig(text, "test.json");
    ASSERT_FALSE(parsed.ok()) << text;
    EXPECT_EQ(parsed.status().code(), ErrorCode::BadInput) << text;
    EXPECT_EQ(parsed.status().message(), thrown([&] { parseCullerConfig(text, "test.json"); }));
  }
  const Result<CullerConfig> missing = tryLoadCullerConfig("/nonexistent/logrid.json");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.status().code(), ErrorCode::Environment);
}

// A depth source that fails its `fail_at`-th request (counting from 1) as a renderer
// error would: the request is answered "nothing drawn" and the error kept.
class FailingSource final : public DepthSource, public KeyReader {
 public:
  explicit FailingSource(cpu::SoftwareDepthBuffer& inner) : inner_(inner) {}
  DepthSourceTraits traits() const override { return inner_.traits(); }
  Status beginFrame(const Camera& camera) override {
    if (refuse_frames > 0) {
      --refuse_frames;
      return Status(ErrorCode::Runtime, "FailingSource: no frame today");
    }
    return inner_.beginFrame(camera);
  }
  void submit(const AreaRequest* requests, std::size_t count, AreaAnswer* answers) override {
    for (std::size_t i = 0; i < count; ++i) {
      if (++requests_ == fail_at) {
        fail(Status(ErrorCode::Runtime,
                    "FailingSource: the renderer lost request " + std::to_string(requests_)));
        answers[i] = conservativeAnswer(requests[i]);
      } else {
        inner_.submit(requests + i, 1, answers + i);
      }
    }
  }
  void readKeys(const PixelRect& rect, float* keys) override { inner_.readKeys(rect, keys); }
  std::uint64_t requests() const { return requests_; }

  std::uint64_t fail_at = 0;  // 0: never
  int refuse_frames = 0;

 private:
  cpu::SoftwareDepthBuffer& inner_;
  std::uint64_t requests_ = 0;
};

// One frame through the result forms; returns the objects drawn, or the first error.
Result<std::set<ObjectId>> pullFrame(Culler& culler, const test::BoxWorld& world, const Camera& cam,
                                     cpu::SoftwareDepthBuffer& depth, DepthSource& source) {
  depth.clear();
  cpu::SoftwareRasterizer raster(cam, depth, nullptr);
  if (Status begun = culler.tryBeginFrame(cam, world.hierarchy, {&source}); !begun) return begun;
  std::set<ObjectId> drawn;
  for (;;) {
    Result<DrawBatch> batch = culler.tryNextBatch();
    if (!batch) return batch.status();
    if (batch->empty()) break;
    for (ObjectId id : *batch) {
      test::drawBox(raster, world.boxes[id], id);
      drawn.insert(id);
    }
  }
  const Result<FrameStats> stats = culler.tryEndFrame();
  if (!stats) return stats.status();
  EXPECT_EQ(stats->objects_drawn, drawn.size());
  return drawn;
}

TEST(ResultForms, ASourcesErrorEndsTheFrameAndTheNextFrameCullsAsBefore) {
  const test::BoxWorld world = test::makeBoxWorld(5);
  const Camera cam = test::boxCamera(96, 72, DepthConvention::Standard, 0.1);
  cpu::SoftwareDepthBuffer depth(cam.width, cam.height, cam.depth.convention);
  FailingSource source(depth);
  for (const Method method : {Method::LogState, Method::LogZfar}) {
    SCOPED_TRACE(toString(method));
    CullerDesc desc;
    desc.method = method;
    desc.tile_size = 8;
    Result<Culler> culler = Culler::create(desc);
    ASSERT_TRUE(culler.ok());

    // Healthy: every visible box drawn.
    const Result<std::set<ObjectId>> healthy = pullFrame(*culler, world, cam, depth, source);
    ASSERT_TRUE(healthy.ok()) << healthy.status().message();
    for (ObjectId id : test::visibleBoxes(world.boxes, cam)) EXPECT_TRUE(healthy->count(id)) << id;

    // Its third request fails: the batch that made it reports it, and the frame is over.
    ASSERT_GT(source.requests(), 3u) << "a frame reads more than that";
    source.fail_at = source.requests() + 3;
    const Result<std::set<ObjectId>> failed = pullFrame(*culler, world, cam, depth, source);
    ASSERT_FALSE(failed.ok());
    EXPECT_EQ(failed.status().code(), ErrorCode::Runtime);
    EXPECT_NE(failed.status().message().find("lost request " + std::to_string(source.fail_at)),
              std::string::npos)
        << failed.status().message();
    const Result<DrawBatch> after = culler->tryNextBatch();
    ASSERT_FALSE(after.ok()) << "the frame went on after its source's error";
    EXPECT_NE(after.status().message().find("only inside a frame"), std::string::npos);
    EXPECT_TRUE(source.takeError().ok()) << "the culler took the error";

    // Refused at the start of a frame: reported by tryBeginFrame, nothing begun.
    source.refuse_frames = 1;
    const Result<std::set<ObjectId>> refused = pullFrame(*culler, world, cam, depth, source);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.status().message().find("no frame today"), std::string::npos);

    // And then the same frame as the healthy one.
    source.fail_at = 0;
    const Result<std::set<ObjectId>> again = pullFrame(*culler, world, cam, depth, source);
    ASSERT_TRUE(again.ok()) << again.status().message();
    EXPECT_EQ(*again, *healthy);
  }
}

TEST(ResultForms, TryCullFrameIsTheCallbackFormWithoutExceptions) {
  const test::BoxWorld world = test::makeBoxWorld(8);
  const Camera cam = test::boxCamera(96, 72, DepthConvention::Reversed, -0.1);
  cpu::SoftwareDepthBuffer depth(cam.width, cam.height, cam.depth.convention);
  Culler thrower, returner;
  std::vector<ObjectId> a, b;
  {
    cpu::SoftwareRasterizer raster(cam, depth, nullptr);
    thrower.cullFrame(cam, world.hierarchy, depth, [&](ObjectId id) {
      test::drawBox(raster, world.boxes[id], id);
      a.push_back(id);
    });
  }
  depth.clear();
  {
    cpu::SoftwareRasterizer raster(cam, depth, nullptr);
    const Result<FrameStats> stats =
        returner.tryCullFrame(cam, world.hierarchy, {&depth}, [&](ObjectId id) {
          test::drawBox(raster, world.boxes[id], id);
          b.push_back(id);
        });
    ASSERT_TRUE(stats.ok()) << stats.status().message();
    EXPECT_EQ(stats->objects_drawn, b.size());
  }
  EXPECT_EQ(a, b);
  // Misuse within a frame is reported and leaves the frame going.
  ASSERT_TRUE(returner.tryBeginFrame(cam, world.hierarchy, {&depth}).ok());
  const Status clear = returner.tryNoteDepthCleared(2.0f);
  EXPECT_EQ(clear.code(), ErrorCode::InvalidArgument);
  EXPECT_TRUE(returner.tryNextBatch().ok());
  returner.abandonFrame();
  // An invalid camera: the camera's own message, and no frame begun.
  Camera broken = cam;
  broken.width = 0;
  const Status begun = returner.tryBeginFrame(broken, world.hierarchy, {&depth});
  EXPECT_EQ(begun.code(), ErrorCode::InvalidArgument);
  EXPECT_EQ(begun.message(), validateCamera(broken));
  EXPECT_FALSE(returner.tryEndFrame().ok());
}

TEST(ResultForms, ARefusedOccluderObjectLeavesTheSetAsItWas) {
  cpu::OccluderMeshes meshes;
  const float good[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint32_t tri[3] = {0, 1, 2};
  ASSERT_TRUE(meshes.tryAddObject(good, 3, tri, 3).ok());
  const std::size_t vertices = meshes.vertexCount();
  // Its third vertex is NaN: refused after two were welded.
  const float bad[9] = {5, 5, 5, 6, 5, 5, 5, 6, std::numeric_limits<float>::quiet_NaN()};
  const Result<std::uint32_t> refused = meshes.tryAddObject(bad, 3, tri, 3);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("positions must be finite"), std::string::npos);
  EXPECT_EQ(meshes.vertexCount(), vertices) << "the refused object's vertices stayed";
  EXPECT_EQ(meshes.objectCount(), 1u);
  const Result<std::uint32_t> next = meshes.tryAddObject(good, 3, tri, 3);
  ASSERT_TRUE(next.ok());
  EXPECT_EQ(meshes.object(*next).first_vertex, vertices);
  EXPECT_EQ(meshes.trySetInsideSolid(7, cpu::kNoOccluder).code(), ErrorCode::InvalidArgument);
}

}  // namespace
}  // namespace logrid
