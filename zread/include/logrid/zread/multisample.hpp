// Multisampled depth buffers for the GL depth sources.
//
// glReadPixels cannot read a multisampled framebuffer (GL_INVALID_OPERATION), and a
// resolving blit keeps one sample of each pixel, which may be a nearer one than another
// sample of the same pixel shows: reading it would make the pixel look more occluded than
// it is. The resolver instead writes, per pixel, the *farthest* sample's depth (the
// largest window depth for the standard convention, the smallest for the reversed one)
// into a single-sampled 32-bit float depth buffer of the same size, which the sources
// read as GL_DEPTH_COMPONENT / GL_FLOAT. A pixel is then occluded for a box only if every
// sample of it is: the test stays conservative for any sample the box could cover.
//
// The multisampled depth attachment may be
//   * a GL_TEXTURE_2D_MULTISAMPLE texture: a shader fetches its samples directly;
//   * a multisampled renderbuffer, or a layer of a GL_TEXTURE_2D_MULTISAMPLE_ARRAY: the
//     rectangles to resolve are first copied (glCopyImageSubData, which no draw state
//     affects) into a multisampled texture of the same format and sample count.
// The default framebuffer's samples cannot be fetched: a multisampled default framebuffer
// is refused with a logrid::Error (render into a framebuffer object instead).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>

#include "logrid/camera.hpp"
#include "logrid/error.hpp"
#include "logrid/types.hpp"
#include "logrid/zread/gl_state.hpp"

namespace logrid::zread {

// What a framebuffer's depth attachment is.
struct DepthAttachment {
  std::uint32_t framebuffer = 0;
  std::int32_t samples = 0;       // 0: single-sampled
  std::uint32_t object_type = 0;  // GL_TEXTURE, GL_RENDERBUFFER or GL_FRAMEBUFFER_DEFAULT
  std::uint32_t name = 0;         // texture or renderbuffer name
  std::uint32_t target = 0;       // texture target (textures only)
  std::int32_t layer = 0;         // attached layer (array textures only)
  std::uint32_t internal_format = 0;
  std::int32_t width = 0, height = 0;
};

// Both forms of each (logrid/error.hpp).
// Queries the depth attachment of `framebuffer` (0: the default framebuffer); an error
// (InvalidArgument) naming `who` if it has none.
Result<DepthAttachment> tryDescribeDepthAttachment(const char* who, std::uint32_t framebuffer);
DepthAttachment describeDepthAttachment(const char* who, std::uint32_t framebuffer);

// An error naming `who` if `framebuffer`'s depth is multisampled but `camera.multisample`
// is false (the projection would count only pixels whose centres a box covers, while
// samples elsewhere in a pixel show it), or if it is a multisampled default framebuffer
// (its samples cannot be resolved conservatively).
Status tryCheckMultisample(const char* who, const DepthAttachment& attachment,
                           const Camera& camera);
void checkMultisample(const char* who, const DepthAttachment& attachment, const Camera& camera);

class MultisampleResolver {
 public:
  // Needs a current GL 4.5 context (compiles its program: a driver that cannot compile it
  // is ErrorCode::Runtime with its log).
  static Result<std::unique_ptr<MultisampleResolver>> create();
  MultisampleResolver();
  ~MultisampleResolver();
  MultisampleResolver(const MultisampleResolver&) = delete;
  MultisampleResolver& operator=(const MultisampleResolver&) = delete;

  // Writes the farthest sample of every pixel of `rects` (inside the attachment) of the
  // multisampled `attachment` into the resolved buffer, using `scope` (whose state it
  // sets and the scope restores). Returns the framebuffer to read the resolved depth from
  // (GL_DEPTH_COMPONENT, GL_FLOAT; only the resolved rectangles are defined), or nothing
  // once the scope failed (an attachment it cannot resolve fails it, Unsupported).
  std::optional<std::uint32_t> resolve(GlStateGuard::Scope& scope,
                                       const DepthAttachment& attachment,
                                       DepthConvention convention, const PixelRect* rects,
                                       std::size_t count);

  // The resolved single-sampled GL_DEPTH_COMPONENT32F texture (0 before the first resolve).
  std::uint32_t depthTexture() const;

 private:
  struct Unbuilt {};
  explicit MultisampleResolver(Unbuilt);
  Status build();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

#if LOGRID_HAS_EXCEPTIONS
inline DepthAttachment describeDepthAttachment(const char* who, std::uint32_t framebuffer) {
  return logrid::orThrow(tryDescribeDepthAttachment(who, framebuffer));
}
inline void checkMultisample(const char* who, const DepthAttachment& attachment,
                             const Camera& camera) {
  logrid::orThrow(tryCheckMultisample(who, attachment, camera));
}
inline MultisampleResolver::MultisampleResolver() : MultisampleResolver(Unbuilt{}) {
  logrid::orThrow(build());
}
#endif

}  // namespace logrid::zread
