// The example of an application's own, non-GL depth source (samples/example/
// readback_source.hpp, over logrid::PixelSource): a CPU rasteriser stands in for a Vulkan
// renderer, its depth buffer for the read-back buffer. Culled through it, a box world
// shows every box a full render shows, boxes are culled, and the "renderer" copies its
// depth once per batch of reads, not once per read.
#include <gtest/gtest.h>

#include <set>

#include "box_world.hpp"
#include "logrid/logrid.hpp"
#include "readback_source.hpp"

namespace logrid {
namespace {

TEST(ReadbackSourceTest, CullsWithoutMissesAndCopiesOncePerBatch) {
  const test::BoxWorld world = test::makeBoxWorld(7);
  for (DepthConvention convention : {DepthConvention::Standard, DepthConvention::Reversed}) {
    for (std::uint32_t lookahead : {1u, 16u}) {
      SCOPED_TRACE(std::string(toString(convention)) + " K=" + std::to_string(lookahead));
      const Camera cam = test::boxCamera(160, 96, convention, 0.2);
      cpu::SoftwareDepthBuffer image(cam.width, cam.height, convention);  // the GPU's image
      image.clear();
      std::uint64_t copies = 0;
      example::ReadbackSource source(cam.width, cam.height, convention, [&] {
        ++copies;
        return image.data();
      });
      cpu::SoftwareRasterizer raster(cam, image, nullptr);
      CullerDesc desc;
      desc.lookahead = lookahead;
      Culler culler(desc);
      std::set<ObjectId> drawn;
      culler.beginFrame(cam, world.hierarchy, {&source});
      for (DrawBatch batch = culler.nextBatch(); !batch.empty(); batch = culler.nextBatch()) {
        for (ObjectId id : batch) {
          test::drawBox(raster, world.boxes[id], id);
          drawn.insert(id);
        }
      }
      const FrameStats stats = culler.endFrame();

      for (ObjectId id : test::visibleBoxes(world.boxes, cam)) {
        EXPECT_TRUE(drawn.count(id)) << "visible box " << id << " was culled";
      }
      EXPECT_GT(stats.boxes_occluded, 0u);
      EXPECT_GT(stats.reads, 0u);
      EXPECT_GT(copies, 0u);
      EXPECT_LE(copies, stats.batches) << "at most one copy per batch of reads";
      if (lookahead > 1) {
        EXPECT_LT(copies, stats.reads);
      }
    }
  }
}

TEST(ReadbackSourceTest, RefusesACameraForAnotherBuffer) {
  example::ReadbackSource source(64, 64, DepthConvention::Standard,
                                 [] { return static_cast<const float*>(nullptr); });
  Camera cam = test::boxCamera(32, 64, DepthConvention::Standard, 0.0);
  const Status refused = source.beginFrame(cam);
  EXPECT_EQ(refused.code(), ErrorCode::InvalidArgument);
  EXPECT_NE(refused.message().find("32x64"), std::string::npos) << refused.message();
}

// A source that answers the grid's requests but is no KeyReader: the lazy grid culls with
// it, and hzb (the one method that reads whole areas as keys) refuses it by name.
class SummariesOnly final : public DepthSource {
 public:
  explicit SummariesOnly(cpu::SoftwareDepthBuffer& buffer) : buffer_(buffer) {}
  DepthSourceTraits traits() const override { return {"summaries-only", true, false}; }
  Status beginFrame(const Camera& camera) override { return buffer_.beginFrame(camera); }
  void submit(const AreaRequest* requests, std::size_t count, AreaAnswer* answers) override {
    buffer_.submit(requests, count, answers);
  }

 private:
  cpu::SoftwareDepthBuffer& buffer_;
};

TEST(ReadbackSourceTest, OnlyHzbNeedsAKeyReader) {
  const test::BoxWorld world = test::makeBoxWorld(3);
  const Camera cam = test::boxCamera(96, 64, DepthConvention::Standard, 0.0);
  cpu::SoftwareDepthBuffer image(cam.width, cam.height, cam.depth.convention);
  image.clear();
  SummariesOnly source(image);
  Culler grid_culler;
  EXPECT_NO_THROW(grid_culler.cullFrame(cam, world.hierarchy, source, [](ObjectId) {}));
  CullerDesc desc;
  desc.method = Method::Hzb;
  Culler hzb(desc);
  try {
    hzb.cullFrame(cam, world.hierarchy, source, [](ObjectId) {});
    ADD_FAILURE() << "hzb culled with a source that is no KeyReader";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("KeyReader"), std::string::npos) << e.what();
  }
  example::ReadbackSource readback(cam.width, cam.height, cam.depth.convention,
                                   [&] { return static_cast<const float*>(image.data()); });
  image.clear();
  EXPECT_NO_THROW(hzb.cullFrame(cam, world.hierarchy, readback, [](ObjectId) {}));
}

}  // namespace
}  // namespace logrid
