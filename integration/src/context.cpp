#include "logrid/gl/context.hpp"

#include <dlfcn.h>
#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstdio>
#include <cstring>
#include <mutex>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

namespace logrid::gl {

const char* toString(Platform p) {
  switch (p) {
    case Platform::Auto: return "auto";
    case Platform::Surfaceless: return "surfaceless";
    case Platform::Device: return "device";
  }
  return "?";
}

std::optional<Platform> parsePlatform(const std::string& name) {
  for (Platform p : {Platform::Auto, Platform::Surfaceless, Platform::Device}) {
    if (name == toString(p)) return p;
  }
  return std::nullopt;
}

namespace {

// Errors reported through the debug callback since the last check.
std::mutex g_debug_mutex;
std::string g_debug_errors;

void GLAPIENTRY debugCallback(GLenum, GLenum type, GLuint, GLenum severity, GLsizei,
                              const GLchar* message, const void*) {
  if (type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH) {
    std::lock_guard<std::mutex> lock(g_debug_mutex);
    if (g_debug_errors.size() < 4096) {
      g_debug_errors += message;
      g_debug_errors += "; ";
    }
  }
}

std::string eglErrorName(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: {
      std::ostringstream out;
      out << "0x" << std::hex << e;
      return out.str();
    }
  }
}

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  }
  return false;
}

// libepoxy aborts the process if libEGL is missing; find out first, and say so.
Status requireLibEgl() {
  void* handle = dlopen("libEGL.so.1", RTLD_LAZY | RTLD_LOCAL);
  if (!handle) {
    return Status(
        ErrorCode::Environment,
        "EGL: libEGL.so.1 could not be loaded. Install an EGL implementation: on Debian "
        "'apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri' (Mesa, works without a GPU), "
        "or your GPU vendor's driver.");
  }
  dlclose(handle);
  return {};
}

struct Device {
  EGLDeviceEXT handle;
  std::string extensions;
  bool software;
};

std::vector<Device> listDevices() {
  std::vector<Device> out;
  EGLint n = 0;
  if (!eglQueryDevicesEXT(0, nullptr, &n) || n <= 0) return out;
  std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(n));
  if (!eglQueryDevicesEXT(n, devices.data(), &n)) return out;
  for (EGLint i = 0; i < n; ++i) {
    const char* ext = eglQueryDeviceStringEXT(devices[std::size_t(i)], EGL_EXTENSIONS);
    Device d{devices[std::size_t(i)], ext ? ext : "", false};
    d.software = hasExtension(ext, "EGL_MESA_device_software");
    out.push_back(d);
  }
  return out;
}

Status checkDesc(const ContextDesc& desc) {
  if (desc.platform != Platform::Auto && desc.platform != Platform::Surfaceless &&
      desc.platform != Platform::Device) {
    std::ostringstream out;
    out << "EGL: unknown platform " << int(desc.platform) << "; use auto, surfaceless or device";
    return Status(ErrorCode::InvalidArgument, out.str());
  }
  if (desc.device_index < -1) {
    std::ostringstream out;
    out << "EGL: device index " << desc.device_index
        << " is invalid; use -1 (the first GPU) or an index from 0";
    return Status(ErrorCode::InvalidArgument, out.str());
  }
  return {};
}

// The EGL platform and device the context is made on.
struct PlatformChoice {
  Platform platform = Platform::Surfaceless;
  std::optional<Device> device;  // Platform::Device only
};

Result<PlatformChoice> choosePlatform(const ContextDesc& desc) {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!client) {
    return Status(ErrorCode::Environment,
                  "EGL: the EGL library reports no client extensions (EGL 1.5 or "
                  "EGL_EXT_client_extensions is required). Install Mesa's EGL (libegl-mesa0) or a "
                  "current GPU driver.");
  }
  const bool has_surfaceless = hasExtension(client, "EGL_MESA_platform_surfaceless");
  const bool has_device = hasExtension(client, "EGL_EXT_platform_device") &&
                          hasExtension(client, "EGL_EXT_device_enumeration") &&
                          hasExtension(client, "EGL_EXT_device_query");
  std::vector<Device> devices = has_device ? listDevices() : std::vector<Device>{};

  PlatformChoice choice{desc.platform, std::nullopt};
  if (choice.platform != Platform::Surfaceless) {
    if (desc.device_index >= 0) {
      if (std::size_t(desc.device_index) >= devices.size()) {
        std::ostringstream out;
        out << "EGL: device index " << desc.device_index << " requested but " << devices.size()
            << " EGL device(s) found; use an index below that, or the "
               "surfaceless platform";
        return Status(ErrorCode::InvalidArgument, out.str());
      }
      choice.device = devices[std::size_t(desc.device_index)];
    } else {
      for (const Device& d : devices) {
        if (!d.software) {
          choice.device = d;
          break;
        }
      }
    }
  }
  if (choice.platform == Platform::Auto) {
    choice.platform = choice.device ? Platform::Device : Platform::Surfaceless;
  }
  if (choice.platform == Platform::Device && !choice.device) {
    return Status(ErrorCode::Environment,
                  has_device
                      ? "EGL: platform 'device' requested but no hardware EGL device was found "
                        "(only Mesa's software device). Install the GPU driver (e.g. the NVIDIA "
                        "driver with its EGL library) or use platform 'surfaceless'."
                      : "EGL: platform 'device' requested but EGL_EXT_platform_device is not "
                        "available. Install a driver that provides it (NVIDIA, or Mesa >= 20) or "
                        "use platform 'surfaceless'.");
  }
  if (choice.platform == Platform::Surfaceless && !has_surfaceless) {
    return Status(
        ErrorCode::Environment,
        "EGL: EGL_MESA_platform_surfaceless is not available. Install Mesa's EGL "
        "('apt-get install libegl-mesa0 libgl1-mesa-dri') or use platform 'device' on a GPU.");
  }
  if (choice.platform != Platform::Device) choice.device.reset();
  return choice;
}

// An initialised display of the chosen platform, bound to desktop OpenGL.
Result<EGLDisplay> openDisplay(const PlatformChoice& choice) {
  const EGLDisplay display =
      choice.platform == Platform::Device
          ? eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, choice.device->handle, nullptr)
          : eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0, minor = 0;
  if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor)) {
    return Status(
        ErrorCode::Environment,
        std::string("EGL: could not open a display on platform '") + toString(choice.platform) +
            "' (" + eglErrorName(eglGetError()) +
            "). Check that the driver is installed (Mesa: libegl-mesa0 libgl1-mesa-dri) and "
            "that /dev/dri is accessible when using a GPU; EGL_LOG_LEVEL=debug shows details.");
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    return Status(ErrorCode::Unsupported,
                  "EGL: the display does not support desktop OpenGL (eglBindAPI "
                  "failed: " +
                      eglErrorName(eglGetError()) + ")");
  }
  return display;
}

// An OpenGL 4.5 core context (with a debug context when asked).
Result<EGLContext> createContext(EGLDisplay display, bool debug) {
  const char* display_ext = eglQueryString(display, EGL_EXTENSIONS);
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!hasExtension(display_ext, "EGL_KHR_no_config_context")) {
    const EGLint attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                              EGL_OPENGL_BIT, EGL_NONE};
    EGLint n = 0;
    if (!eglChooseConfig(display, attribs, &config, 1, &n) || n < 1) {
      return Status(ErrorCode::Unsupported,
                    "EGL: no config supports desktop OpenGL on this display");
    }
  }
  const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                    4,
                                    EGL_CONTEXT_MINOR_VERSION,
                                    5,
                                    EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                    EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                    EGL_CONTEXT_OPENGL_DEBUG,
                                    debug ? EGL_TRUE : EGL_FALSE,
                                    EGL_NONE};
  const EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attribs);
  if (context == EGL_NO_CONTEXT) {
    return Status(ErrorCode::Unsupported,
                  std::string("EGL: could not create an OpenGL 4.5 core context (") +
                      eglErrorName(eglGetError()) +
                      "). logrid needs OpenGL 4.5: Mesa >= 20 (llvmpipe works without a GPU) or a "
                      "current vendor driver. Do not set GALLIUM_DRIVER=softpipe.");
  }
  return context;
}

// What the current context reports; ErrorCode::Unsupported below OpenGL 4.5.
Result<ContextInfo> readInfo(const PlatformChoice& choice) {
  ContextInfo info;
  info.platform = choice.platform;
  info.device = choice.device ? choice.device->extensions : "default display";
  auto str = [](GLenum e) {
    const auto* v = reinterpret_cast<const char*>(glGetString(e));
    return std::string(v ? v : "");
  };
  info.vendor = str(GL_VENDOR);
  info.renderer = str(GL_RENDERER);
  info.version = str(GL_VERSION);
  info.software = info.renderer.find("llvmpipe") != std::string::npos ||
                  info.renderer.find("softpipe") != std::string::npos ||
                  info.renderer.find("swrast") != std::string::npos;
  if (epoxy_gl_version() < 45) {
    return Status(ErrorCode::Unsupported,
                  "GL: the context reports version " + info.version +
                      "; logrid needs OpenGL 4.5 core. Update Mesa or the driver.");
  }
  return info;
}

}  // namespace

struct Context::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  ContextInfo info;
};

Context::Context(Unopened) : impl_(std::make_unique<Impl>()) {}

Result<std::unique_ptr<Context>> Context::create(const ContextDesc& desc) {
  std::unique_ptr<Context> context(new Context(Unopened{}));
  if (Status s = context->open(desc); !s) return s;
  return Result<std::unique_ptr<Context>>(std::move(context));
}

Status Context::open(const ContextDesc& desc) {
  if (Status s = checkDesc(desc); !s) return s;
  if (Status s = requireLibEgl(); !s) return s;
  const Result<PlatformChoice> choice = choosePlatform(desc);
  if (!choice) return choice.status();
  Impl& s = *impl_;
  const Result<EGLDisplay> display = openDisplay(choice.value());
  if (!display) return display.status();
  s.display = display.value();
  const Result<EGLContext> context = createContext(s.display, desc.debug);
  if (!context) return context.status();
  s.context = context.value();
  if (Status made = tryMakeCurrent(); !made) return made;
  Result<ContextInfo> info = readInfo(choice.value());
  if (!info) return info.status();
  s.info = std::move(info).value();
  s.info.debug = installDebugOutput();
  return tryCheck("Context");
}

Context::~Context() {
  if (impl_->display != EGL_NO_DISPLAY) {
    eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (impl_->context != EGL_NO_CONTEXT) eglDestroyContext(impl_->display, impl_->context);
    eglTerminate(impl_->display);
  }
}

const ContextInfo& Context::info() const { return impl_->info; }

Status Context::tryMakeCurrent() {
  if (!eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context)) {
    return Status(ErrorCode::Runtime, "EGL: eglMakeCurrent failed (" + eglErrorName(eglGetError()) +
                                          "); the driver may not support surfaceless contexts "
                                          "(EGL_KHR_surfaceless_context)");
  }
  return {};
}

Status Context::tryCheck(const char* where) const { return tryCheckGlErrors(where); }

bool installDebugOutput() {
  GLint flags = 0;
  glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
  if ((flags & GL_CONTEXT_FLAG_DEBUG_BIT) == 0) return false;
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(debugCallback, nullptr);
  return true;
}

Status tryCheckGlErrors(const char* where) {
  std::string problems;
  for (int i = 0; i < 16; ++i) {
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    std::ostringstream out;
    out << "glGetError 0x" << std::hex << e << "; ";
    problems += out.str();
  }
  {
    std::lock_guard<std::mutex> lock(g_debug_mutex);
    problems += g_debug_errors;
    g_debug_errors.clear();
  }
  if (!problems.empty())
    return Status(ErrorCode::Runtime, std::string(where) + ": GL error: " + problems);
  return {};
}

}  // namespace logrid::gl
