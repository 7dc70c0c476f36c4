// Renders frames of a walkthrough with one method and one configuration: camera from
// the scene's path, cull and draw through logrid (or the oracle's exact visible set),
// glFinish, then optionally images and the object-ID check. `walk`, `bench` and `tune`
// are loops over FrameRunners; bench interleaves several runners frame by frame so that
// machine drift hits every method alike. `view` renders the cameras a person flies.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/images.hpp"
#include "cli/readers.hpp"
#include "logrid/culler.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/gl/mesh_renderer.hpp"
#include "logrid/gl/object_id_oracle.hpp"
#include "scene/prepare.hpp"
#include "scene/view.hpp"

namespace logrid::samples {

// A method as the commands name it: one of logrid::Method's names, or "oracle" (draws
// exactly the visible set found by an ID pass that is not timed: the floor no culling
// method can beat), optionally followed by traversal settings that override the
// command's --lookahead and --coherence: ":K" (a lookahead, or ":all") and ":tc"
// (temporal coherence), e.g. "log-state:16:tc".
struct MethodChoice {
  MethodChoice() = default;
  MethodChoice(std::optional<Method> m) : method(m) {}  // NOLINT: implicit on purpose

  std::optional<Method> method;  // empty: oracle
  std::optional<std::uint32_t> lookahead;
  bool coherence = false;
  std::string name() const;
};
std::optional<MethodChoice> parseMethodChoice(const std::string& name);

// Calls into a frame, for tests that act as an application with state of its own (the
// GL-state fuzz test). Each is optional.
struct FrameHooks {
  // The frame's buffers were just cleared (the culled frame and the ID pass alike).
  std::function<void()> after_clear;
  // Right before and right after Culler::cullFrame (the culled frame only).
  std::function<void()> before_cull;
  std::function<void()> after_cull;
  // Inside the draw callback, around the renderer's draw. With before_draw set, the
  // runner binds its framebuffer and renderer again after it (as an application that
  // leaves other bindings between its draws would).
  std::function<void()> before_draw;
  std::function<void()> after_draw;
};

struct RunConfig {
  MethodChoice method{Method::LogState};
  CullerDesc culler;                  // method is taken from `method`
  std::string reader = "readpixels";  // a name of readerTable()
  ViewSettings view;
  std::size_t frames = 100;  // frames spread over the path's first `span`
  double span = 1.0;         // fraction of the path the frames cover (0, 1]
  bool verify = false;       // object-ID check after each frame
  std::string images_dir;    // write PNG frames here when set
  bool overlay = false;      // and overlay pictures (tile grid, boxes); records what
                             // overlayData() returns
  FrameHooks hooks;
};

struct FrameRecord {
  std::size_t frame = 0;
  double ms = 0;  // clear + cull + draw + glFinish
  FrameStats stats;
  std::uint64_t triangles = 0;         // triangles drawn
  std::int64_t visible = -1;           // objects in the ID buffer (with verify or oracle)
  std::int64_t missed = -1;            // visible objects not drawn (with verify)
  std::int64_t artifacts = -1;         // objects shown only through depth-extrapolated fragments
  std::int64_t missed_artifacts = -1;  // of those, not drawn (reported apart, see
                                       // logrid/gl/object_id_oracle.hpp)
  std::vector<ObjectId> missed_ids;    // the first few (all of them: missedObjects())
};

// The visible set of each frame found by the object-ID oracle (gl::objectIdOracle),
// shared by runners that render the same frames with the same view (bench cells), so the
// pass runs once per frame.
struct OracleCache {
  std::vector<std::optional<gl::OracleFrame>> frames;
};

class FrameRunner {
 public:
  // Needs a current GL context and a renderer of the scene. Throws logrid::Error for a
  // configuration that cannot run (bad size, format, tile size, method and reader).
  FrameRunner(const PreparedScene& scene, gl::MeshRenderer& renderer, const RunConfig& config);
  ~FrameRunner();

  const RunConfig& config() const { return config_; }
  FrameRecord renderFrame(std::size_t frame);
  // Renders any camera of the configured view (size and depth set-up as config().view),
  // e.g. one a person flies; the ID pass (verify, oracle) is not shared with other runners.
  // `frame` only labels the record and image files.
  FrameRecord renderCamera(const Camera& camera, std::size_t frame);
  // The camera of a frame (for callers that need it, e.g. overlays and tests).
  Camera cameraFor(std::size_t frame) const;
  // Share ID-pass results with other runners of the same frames and view.
  void shareOracle(std::shared_ptr<OracleCache> cache) { oracle_cache_ = std::move(cache); }
  // Last frame's colour image (RGBA8, bottom-up rows).
  std::vector<std::uint8_t> readColor() const { return framebuffer_->readColor(); }
  // The framebuffer the frames are drawn into (colour attachment 0 holds the picture).
  const gl::Framebuffer& framebuffer() const { return *framebuffer_; }

  // What the last frame did, for overlays and viewers:
  // the grid, the tested boxes and the drawn leaf boxes (recorded when config().overlay);
  OverlayData overlayData() const;
  // the objects drawn;
  const std::vector<ObjectId>& drawnObjects() const { return drawn_list_; }
  // the visible objects not drawn (verify), every one of them.
  const std::vector<ObjectId>& missedObjects() const { return missed_; }

 private:
  gl::OracleFrame idPass(const Camera& camera);
  // The ID pass of a frame, from the shared cache when another runner did it.
  gl::OracleFrame visibleSet(std::optional<std::size_t> frame, const Camera& camera);
  FrameRecord render(const Camera& camera, std::size_t frame, bool cached);
  void writeImages(std::size_t frame, const Camera& camera);

  const PreparedScene& scene_;
  gl::MeshRenderer& renderer_;
  RunConfig config_;
  std::unique_ptr<gl::Framebuffer> framebuffer_;
  std::unique_ptr<FrameReader> reader_;
  std::unique_ptr<Culler> culler_;
  std::unique_ptr<Culler> vfc_;  // for the ID pass
  struct Observer;
  std::unique_ptr<Observer> observer_;
  std::vector<std::uint8_t> drawn_;  // per object, this frame
  std::vector<ObjectId> drawn_list_;
  std::vector<ObjectId> missed_;
  std::shared_ptr<OracleCache> oracle_cache_;
};

}  // namespace logrid::samples
