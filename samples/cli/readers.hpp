// The depth readers a walkthrough can cull with, each described in one place: the
// table in readers.cpp. A reader is a logrid::DepthSource plus what the frame runner
// must do for it: software readers are fed the triangles of every object drawn.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "logrid/depth_source.hpp"
#include "logrid/method.hpp"
#include "logrid/projection.hpp"
#include "scene/motion.hpp"
#include "scene/prepare.hpp"

namespace logrid::samples {

struct CpuReaderOptions;  // cli/cpu_reader.hpp

// A depth source as a frame uses it.
class FrameReader {
 public:
  virtual ~FrameReader() = default;
  virtual DepthSource& source() = 0;
  // Before the frame is culled (the framebuffer is cleared).
  virtual void beginFrame(const Camera& camera) { (void)camera; }
  // After the renderer drew object `id` through the culler's callback.
  virtual void objectDrawn(ObjectId id) { (void)id; }
  // Its source's reads leave their GL state set (GlStatePolicy::ApplicationManaged): the
  // runner sets what it draws with again before each batch.
  virtual bool leavesGlState() const { return false; }
};

// What a reader is made from.
struct ReaderContext {
  const PreparedScene& scene;
  std::uint32_t framebuffer;  // the GL framebuffer the frame draws into
  std::uint32_t width;
  std::uint32_t height;
  DepthSetup depth;
  // The movers' transforms of the current frame (objects from scene.static_objects on);
  // nullptr or empty when nothing moves.
  const MotionFrame* motion = nullptr;
  const CpuReaderOptions* cpu = nullptr;  // the cpu reader's settings (nullptr: defaults)
  ProjectionSettings projection;          // the culler's
  Method method = Method::LogZfar;        // the culler's
};

struct ReaderInfo {
  const char* name;
  const char* description;  // one line
  bool reads_depth;         // answers Summary requests (else counts only)
  bool reads_framebuffer;   // reads the GL framebuffer (else a CPU buffer it is fed)
  std::function<std::unique_ptr<FrameReader>(const ReaderContext&)> make;
};

const std::vector<ReaderInfo>& readerTable();
// The reader of that name, or nullptr.
const ReaderInfo* findReader(const std::string& name);
// "readpixels, pbo, ..." for messages and help texts.
std::string readerNames();

}  // namespace logrid::samples
