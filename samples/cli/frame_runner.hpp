// Renders frames of a walkthrough with one method and one configuration: camera from
// the scene's path, cull and draw through logrid (or the oracle's exact visible set),
// glFinish, then optionally images and the object-ID check. `walk`, `bench` and `tune`
// are loops over FrameRunners; bench interleaves several runners frame by frame so that
// machine drift hits every method alike.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/readers.hpp"
#include "logrid/culler.hpp"
#include "logrid/ddo/selector.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/gl/mesh_renderer.hpp"
#include "logrid/gl/object_id_oracle.hpp"
#include "logrid/gl/occluder_renderer.hpp"
#include "scene/prepare.hpp"
#include "scene/view.hpp"

namespace logrid::samples {

// How a run uses the directional discretized occluders (DDO; scene/ddo_scene.hpp,
// logrid/ddo/selector.hpp).
enum class DdoUse : std::uint8_t {
  None,
  Culler,     // "ddo": the paper's culler (§4): octree walk, occlusion map, no depth reads
  Occluders,  // "ddo+log": the selected occluders drawn first (depth only), then log-state
};

// A method as the commands name it: one of logrid::Method's names, "ddo", "ddo+log", or
// "oracle" (draws exactly the visible set found by an ID pass that is not timed: the floor
// no culling method can beat), optionally followed by traversal settings that override
// the command's --lookahead and --coherence: ":K" (a lookahead, or ":all") and ":tc"
// (temporal coherence), e.g. "log-state:16:tc" or "ddo+log:16". ddo and the oracle run
// no logrid culler and take no settings.
struct MethodChoice {
  std::optional<Method> method;  // the logrid culler's method, if one runs
  std::optional<std::uint32_t> lookahead;
  bool coherence = false;
  DdoUse ddo = DdoUse::None;
  bool oracle() const { return !method && ddo == DdoUse::None; }
  std::string name() const;
};
std::optional<MethodChoice> parseMethodChoice(const std::string& name);

struct RunConfig {
  MethodChoice method{Method::LogState, std::nullopt, false, DdoUse::None};
  CullerDesc culler;                  // method is taken from `method`
  std::string reader = "readpixels";  // a name of readerTable()
  ViewSettings view;
  std::size_t frames = 100;  // frames spread over the whole path
  bool verify = false;       // object-ID check after each frame
  std::string images_dir;    // write PNG frames here when set
  bool overlay = false;      // and overlay pictures (tile grid, boxes)
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
  std::vector<ObjectId> missed_ids;    // the first few
  std::int64_t occluders = -1;         // DDO: quads drawn first (ddo+log) or faces in the map (ddo)
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
  // The camera of a frame (for callers that need it, e.g. overlays and tests).
  Camera cameraFor(std::size_t frame) const;
  // Share ID-pass results with other runners of the same frames and view.
  void shareOracle(std::shared_ptr<OracleCache> cache) { oracle_cache_ = std::move(cache); }
  // Last frame's colour image (RGBA8, bottom-up rows).
  std::vector<std::uint8_t> readColor() const { return framebuffer_->readColor(); }

 private:
  gl::OracleFrame idPass(const Camera& camera);
  // The ID pass of a frame, from the shared cache when another runner did it.
  gl::OracleFrame visibleSet(std::size_t frame, const Camera& camera);
  void writeImages(std::size_t frame, const Camera& camera);

  const PreparedScene& scene_;
  gl::MeshRenderer& renderer_;
  RunConfig config_;
  std::unique_ptr<gl::Framebuffer> framebuffer_;
  std::unique_ptr<FrameReader> reader_;
  std::unique_ptr<Culler> culler_;
  std::unique_ptr<Culler> vfc_;                              // for the ID pass
  std::unique_ptr<ddo::Selector> selector_;                  // ddo and ddo+log
  std::unique_ptr<gl::OccluderRenderer> occluder_renderer_;  // ddo+log
  std::vector<DrawnArea> occluder_areas_;                    // ddo+log, this frame's
  struct Observer;
  std::unique_ptr<Observer> observer_;
  std::vector<std::uint8_t> drawn_;  // per object, this frame
  std::vector<ObjectId> drawn_list_;
  std::shared_ptr<OracleCache> oracle_cache_;
};

}  // namespace logrid::samples
