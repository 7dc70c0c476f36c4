// A headless OpenGL 4.5 core context through EGL, without a window. (An application
// with a window of its own uses that window's context instead; see installDebugOutput.)
//
// Platforms:
//   Surfaceless  EGL_MESA_platform_surfaceless: Mesa (llvmpipe without a GPU, or a Mesa
//                GPU driver). The default on machines without an NVIDIA device.
//   Device       EGL_EXT_platform_device: a GPU picked from eglQueryDevicesEXT, skipping
//                Mesa's software device. The default where such a device exists.
// The context renders into framebuffer objects (framebuffer.hpp); it has no surface.
//
// Every failure is reported with what failed and what to install or change, in both
// forms (logrid/error.hpp): Context::create() and the try...() calls return it, the
// Context constructor and the other calls throw it as logrid::Error.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "logrid/error.hpp"

namespace logrid::gl {

enum class Platform : std::uint8_t { Auto, Surfaceless, Device };

const char* toString(Platform platform);
std::optional<Platform> parsePlatform(const std::string& name);  // auto|surfaceless|device

struct ContextDesc {
  Platform platform = Platform::Auto;
  int device_index = -1;  // Device platform: index into eglQueryDevicesEXT (-1: first GPU)
#ifdef NDEBUG
  bool debug = false;  // debug context with synchronous debug output
#else
  bool debug = true;
#endif
};

struct ContextInfo {
  Platform platform = Platform::Auto;  // the platform actually used
  std::string device;                  // EGL device extensions, or "default display"
  std::string vendor;                  // GL_VENDOR
  std::string renderer;                // GL_RENDERER
  std::string version;                 // GL_VERSION
  bool debug = false;
  bool software = false;  // llvmpipe / softpipe / swrast
};

class Context {
 public:
  // Creates the context and makes it current on the calling thread. The result form:
  // the context, or ErrorCode::InvalidArgument for a bad desc, ErrorCode::Environment or
  // ErrorCode::Unsupported for what the platform lacks, ErrorCode::Runtime for a failure
  // of EGL or GL.
  static Result<std::unique_ptr<Context>> create(const ContextDesc& desc = {});
  // The throwing form: throws logrid::Error where create() fails.
  explicit Context(const ContextDesc& desc = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const ContextInfo& info() const;
  // Fails with ErrorCode::Runtime when EGL cannot make the context current.
  Status tryMakeCurrent();
  void makeCurrent();

  // ErrorCode::Runtime naming `where` if GL reported an error (glGetError, and in debug
  // contexts any error-type debug message) since the last check.
  Status tryCheck(const char* where) const;
  void check(const char* where) const;

 private:
  struct Unopened {};
  explicit Context(Unopened);  // opens nothing: open() does, and the destructor closes it
  Status open(const ContextDesc& desc);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The same check for code that does not hold the Context (uses the current one).
Status tryCheckGlErrors(const char* where);
void checkGlErrors(const char* where);

// For a context the application made (e.g. a window's, through GLFW or SDL): if the
// current context is a debug context, routes its error messages into checkGlErrors()
// as Context does for its own, and returns true; otherwise returns false. logrid's
// framebuffers, renderer and depth sources need only a current OpenGL 4.5 core context,
// whoever made it.
bool installDebugOutput();

#if LOGRID_HAS_EXCEPTIONS
inline Context::Context(const ContextDesc& desc) : Context(Unopened{}) {
  logrid::orThrow(open(desc));
}
inline void Context::makeCurrent() { logrid::orThrow(tryMakeCurrent()); }
inline void Context::check(const char* where) const { logrid::orThrow(tryCheck(where)); }
inline void checkGlErrors(const char* where) { logrid::orThrow(tryCheckGlErrors(where)); }
#endif

}  // namespace logrid::gl
