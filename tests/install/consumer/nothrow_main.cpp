// A user of an installed logrid that builds with -fno-exceptions: every call that can
// fail through its result form (logrid/error.hpp). Culls three boxes for an empty depth
// buffer as consumer_core does, then checks that the errors a user can cause come back
// as codes and messages: an invalid culler description, an invalid camera, a call
// outside a frame, a depth source that cannot serve the camera, a bad configuration.
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include "logrid/bvh/bvh.hpp"
#include "logrid/cpu/software_depth.hpp"
#include "logrid/logrid.hpp"

#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
#error "consumer_nothrow must be built with -fno-exceptions"
#endif

namespace {

int failures = 0;

void expect(bool ok, const char* what, const logrid::Status& status = {}) {
  if (ok) return;
  ++failures;
  std::printf("consumer_nothrow: FAIL: %s (%s)\n", what, status.message().c_str());
}

// An error with `code` whose message names `part`.
void expectError(const logrid::Status& status, logrid::ErrorCode code, const char* part,
                 const char* what) {
  expect(!status.ok() && status.code() == code && status.message().find(part) != std::string::npos,
         what, status);
  if (!status.ok()) std::printf("consumer_nothrow: %s: %s\n", what, status.message().c_str());
}

}  // namespace

int main() {
  const std::vector<logrid::Aabb> boxes = {
      {{-1, -1, -1}, {1, 1, 1}},     // 0: in front of the camera
      {{-1, -1, 20}, {1, 1, 22}},    // 1: behind the camera
      {{100, -1, -1}, {102, 1, 1}},  // 2: far outside the field of view
  };
  logrid::Result<logrid::bvh::FlatHierarchy> hierarchy = logrid::bvh::tryBuildOverBoxes(boxes);
  expect(hierarchy.ok(), "tryBuildOverBoxes", hierarchy.status());
  if (!hierarchy) return 1;

  logrid::Camera camera;
  camera.width = 64;
  camera.height = 48;
  const logrid::Result<logrid::Mat4d> projection =
      logrid::tryPerspective(1.0, 64.0 / 48.0, 0.5, 100.0, camera.depth);
  const logrid::Result<logrid::Mat4d> view = logrid::tryLookAt({0, 0, 10}, {0, 0, 0}, {0, 1, 0});
  expect(projection.ok() && view.ok(), "tryPerspective, tryLookAt");
  if (!projection || !view) return 1;
  camera.view_projection = logrid::multiply(*projection, *view);
  camera.render_origin = {0, 0, 10};

  logrid::Result<std::unique_ptr<logrid::cpu::SoftwareDepthBuffer>> depth =
      logrid::cpu::SoftwareDepthBuffer::create(64, 48, camera.depth.convention);
  expect(depth.ok(), "SoftwareDepthBuffer::create", depth.status());
  logrid::Result<logrid::Culler> culler = logrid::Culler::create();
  expect(culler.ok(), "Culler::create", culler.status());
  if (!depth || !culler) return 1;

  // A frame in the pull form.
  std::set<logrid::ObjectId> drawn;
  logrid::Status status = culler->tryBeginFrame(camera, *hierarchy, {depth->get()});
  expect(status.ok(), "tryBeginFrame", status);
  for (;;) {
    logrid::Result<logrid::DrawBatch> batch = culler->tryNextBatch();
    expect(batch.ok(), "tryNextBatch", batch.status());
    if (!batch || batch->empty()) break;
    drawn.insert(batch->begin(), batch->end());
  }
  const logrid::Result<logrid::FrameStats> stats = culler->tryEndFrame();
  expect(stats.ok(), "tryEndFrame", stats.status());
  expect(drawn == std::set<logrid::ObjectId>{0}, "exactly object 0 drawn");
  std::printf("consumer_nothrow: drew %zu of %zu objects\n", drawn.size(), boxes.size());

  // The callback form.
  const logrid::Result<logrid::FrameStats> callback =
      culler->tryCullFrame(camera, *hierarchy, {depth->get()}, [&](logrid::ObjectId) {});
  expect(callback.ok() && callback->objects_drawn == 1, "tryCullFrame", callback.status());

  // What a user can get wrong.
  logrid::CullerDesc bad;
  bad.tile_size = 0;
  expectError(logrid::Culler::create(bad).status(), logrid::ErrorCode::InvalidArgument,
              "tile size 0", "an invalid description");
  logrid::Camera broken = camera;
  broken.width = 0;
  expectError(culler->tryBeginFrame(broken, *hierarchy, {depth->get()}),
              logrid::ErrorCode::InvalidArgument, "viewport", "an invalid camera");
  expectError(culler->tryNextBatch().status(), logrid::ErrorCode::InvalidArgument, "inside a frame",
              "a batch outside a frame");
  logrid::Camera wider = camera;
  wider.width = 128;
  wider.view_projection = logrid::multiply(
      logrid::tryPerspective(1.0, 128.0 / 48.0, 0.5, 100.0, wider.depth).value(), *view);
  expectError(culler->tryBeginFrame(wider, *hierarchy, {depth->get()}),
              logrid::ErrorCode::InvalidArgument, "create the buffer to match",
              "a depth source that cannot serve the camera");
  expectError(logrid::tryParseCullerConfig("{\"format\": 1}", "mine.json").status(),
              logrid::ErrorCode::BadInput, "mine.json", "a bad configuration");
  expectError(logrid::bvh::tryBuildOverBoxes({{{0, 0, 0}, {-1, -1, -1}}}).status(),
              logrid::ErrorCode::BadInput, "invalid box", "an inverted box");

  if (failures) return 1;
  std::printf("consumer_nothrow: OK\n");
  return 0;
}
