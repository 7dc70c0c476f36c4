// Renders frames of a walkthrough with one method and one configuration: camera from
// the scene's path, cull and draw through logrid (or the oracle's exact visible set),
// glFinish, then optionally images and the object-ID check. `walk`, `bench` and `tune`
// are loops over FrameRunners; bench interleaves several runners frame by frame so that
// machine drift hits every method alike. `view` renders the cameras a person flies.
//
// The timed part of a frame is the same for every row: the same framebuffer (colour and
// depth, no ID attachment), verified or not, the oracle's included. The object-ID pass
// renders into a framebuffer of its own and never inside a timed frame: before it for
// the oracle (whose timed frame then draws exactly the set it found, as a method draws
// what it culled), after it for the check (RunConfig::verify).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/cpu_reader.hpp"
#include "cli/images.hpp"
#include "cli/readers.hpp"
#include "logrid/bvh/motion.hpp"
#include "logrid/culler.hpp"
#include "logrid/ddo/occluder_pass.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/gl/mesh_renderer.hpp"
#include "logrid/gl/object_id_oracle.hpp"
#include "scene/prepare.hpp"
#include "scene/view.hpp"

namespace logrid::samples {

// A method as the commands name it: one of logrid::Method's names (method.hpp), or "oracle"
// (draws exactly the visible set found by an ID pass that is not timed: the floor no
// culling method can beat), optionally followed by the settings the method takes
// (MethodTakes), which override the command's --lookahead and --coherence: ":K" (a
// lookahead, or ":all") and ":tc" (temporal coherence), e.g. "log-state:16:tc" or
// "ddo+log:16"; log+hwq also takes its query schedule (log+hwq:chc). The oracle runs no
// logrid culler and takes no settings.
struct MethodChoice {
  MethodChoice() = default;
  MethodChoice(std::optional<Method> m) : method(m) {}  // NOLINT: implicit on purpose

  std::optional<Method> method;  // the logrid culler's method; none: the oracle
  std::optional<std::uint32_t> lookahead;
  bool coherence = false;
  // log+hwq: the schedule of the boxes the grid leaves undecided, from a suffix
  // (log+hwq:chc); empty: RunConfig::culler.queries.schedule.
  std::optional<QuerySchedule> schedule;
  bool oracle() const { return !method; }
  std::string name() const;
};
// Nothing for a name that is no method or carries a setting its method does not take;
// then `problem`, if given, says which.
std::optional<MethodChoice> parseMethodChoice(const std::string& name,
                                              std::string* problem = nullptr);
// What --method accepts, for help texts and messages.
std::string methodChoiceHelp();

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

// nohc (and log+hwq scheduled by nohc) needs the hardware parameters of this renderer:
// fills desc.queries.hardware from zread::hardwareParameters() (measured on first use,
// kept per renderer for the process) unless it holds valid ones. Needs a GL context.
void measureHardwareIfNeeded(CullerDesc& desc);

struct RunConfig {
  MethodChoice method{Method::LogState};
  CullerDesc culler;                  // method is taken from `method`
  std::string reader = "readpixels";  // a name of readerTable()
  // The query methods (MethodNeeds::queries) issue their queries through a
  // zread::BoxQuerySource over the frame's framebuffer, of this GL target.
  bool any_samples_passed = false;  // GL_ANY_SAMPLES_PASSED_CONSERVATIVE, else GL_SAMPLES_PASSED
  // The hierarchy culled: "static" (the scene's own, PreparedScene::hierarchy), a name of
  // bvh::motionTable() (built over every object's box and updated each frame), or
  // "auto": static for a scene without moving objects, refit for one with them.
  std::string hierarchy = "auto";
  bvh::MotionDesc motion;  // settings of the motion hierarchies
  CpuReaderOptions cpu;    // for --reader cpu
  ViewSettings view;
  // The application skips the clusters that face away from the eye (clusters.hpp,
  // facesAway) among those the culler hands it: right only where its renderer culls back
  // faces (view.cull_back_faces), so refused without; needs a clustered scene and a
  // perspective view.
  bool backface_clusters = false;
  std::size_t frames = 100;  // frames spread over the whole path
  // > 0: frame f is at path time (first key) + f * time_step instead (the camera stops
  // at the path's end; movers go on): consecutive frames as close as at an interactive
  // rate, for what methods carry from frame to frame (temporal coherence, the query
  // schedules). Untimed paths, as the procedural ones, count time in metres travelled.
  double time_step = 0;
  bool verify = false;     // object-ID check after each frame (untimed)
  std::string images_dir;  // write PNG frames here when set
  bool overlay = false;    // and overlay pictures (tile grid, boxes); records what
                           // overlayData() returns
  FrameHooks hooks;
};

struct FrameRecord {
  std::size_t frame = 0;
  double ms = 0;  // hierarchy update + clear + cull + draw + statistics + glFinish
  FrameStats stats;
  double time = 0;               // the frame's time (motion.hpp)
  bvh::UpdateStats update;       // the motion hierarchy's update (zero for static ones)
  bvh::MeasureStats measure;     // its statistics pass after the frame (ternary)
  std::uint64_t moved = 0;       // objects whose box changed since the last frame
  std::uint64_t triangles = 0;   // triangles drawn
  std::uint64_t draw_calls = 0;  // the renderer's, in the timed part
  std::uint64_t backfacing = 0;  // clusters not drawn for facing away (backface_clusters)
  // Clustered scenes (PreparedScene::clustered()): the objects the drawn clusters and
  // the visible ones (with verify or oracle) belong to; -1 otherwise, where the ids are
  // the objects.
  std::int64_t objects_drawn = -1;
  std::int64_t visible_objects = -1;
  std::int64_t visible = -1;           // objects in the ID buffer (with verify or oracle)
  std::int64_t missed = -1;            // visible objects not drawn (with verify)
  std::int64_t artifacts = -1;         // objects shown only through depth-extrapolated fragments
  std::int64_t missed_artifacts = -1;  // of those, not drawn (reported apart, see
                                       // logrid/gl/object_id_oracle.hpp)
  std::vector<ObjectId> missed_ids;    // the first few (all of them: missedObjects())
  std::int64_t occluders = -1;         // DDO: quads drawn first (ddo+log) or faces in the map (ddo)
  std::optional<CpuFrameStats> cpu;    // with --reader cpu
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
  // The object-ID check after each frame, on or off from the next frame (bench verifies
  // some repetitions only). The frames' framebuffer is the same either way.
  void setVerify(bool verify) { config_.verify = verify; }
  FrameRecord renderFrame(std::size_t frame);
  // Renders the frame from any pose, e.g. one a person flies (moving objects where they
  // are at frameTime(frame)); the ID pass (verify, oracle) is not shared with other
  // runners. `frame` also labels the record and image files.
  FrameRecord renderPose(const CameraPose& pose, std::size_t frame);
  // The camera of a frame (for callers that need it, e.g. overlays and tests).
  Camera cameraFor(std::size_t frame) const;
  // The camera of a pose in the configured view (what renderPose() renders).
  Camera cameraAt(const CameraPose& pose) const;
  CameraPose poseFor(std::size_t frame) const;
  double frameTime(std::size_t frame) const;
  // The hierarchy culled (the scene's static one, one set by setHierarchy(), or the
  // motion hierarchy).
  const Hierarchy& hierarchy() const;

  // Discontinuities between frames, as an application meets them. The culler is kept,
  // with what it remembers of the last frame (temporal coherence, the query schedules'
  // node states); it must itself drop what no longer holds.
  // A new view (a window resized, the depth format or convention changed): the
  // framebuffer, the depth reader and the query source are made again for it, as an
  // application makes its render targets again. Throws logrid::Error as the constructor.
  void setView(const ViewSettings& view);
  // Culls `hierarchy` (the application's own, over the scene's object ids) instead of the
  // scene's static one, from the next frame on; nullptr: the scene's again. Objects it does
  // not hold are out of the scene: the ID pass does not draw them either (objects removed
  // and added between frames). Not owned; must outlive its use. Refused (logrid::Error)
  // for a runner with a motion hierarchy or no culler.
  void setHierarchy(const Hierarchy* hierarchy);
  const bvh::MotionHierarchy* motionHierarchy() const { return dynamic_.get(); }
  // The last frame rendered's motion: every object's box (movers where they were) and
  // the moving objects' transforms.
  const std::vector<Aabb>& objectBoxes() const { return motion_.boxes; }
  const MotionFrame& motionFrame() const { return motion_; }
  // Share ID-pass results with other runners of the same frames and view.
  void shareOracle(std::shared_ptr<OracleCache> cache) { oracle_cache_ = std::move(cache); }
  // Last frame's colour image (RGBA8, bottom-up rows).
  std::vector<std::uint8_t> readColor() const { return framebuffer_->readColor(); }
  // The framebuffer the frames are drawn into (colour attachment 0 holds the picture;
  // no ID attachment: the ID pass has its own, so the frame's depth stays as drawn).
  const gl::Framebuffer& framebuffer() const { return *framebuffer_; }

  // What the last frame did, for overlays and viewers:
  // the grid, the tested boxes and the drawn leaf boxes (recorded when config().overlay);
  OverlayData overlayData() const;
  // the objects drawn;
  const std::vector<ObjectId>& drawnObjects() const { return drawn_list_; }
  // the visible objects not drawn (verify), every one of them.
  const std::vector<ObjectId>& missedObjects() const { return missed_; }

 private:
  // Moves the movers to `time`: boxes, `moved`, and the renderer's transforms.
  void applyMotion(double time);
  // The ID pass's own framebuffer (made on first use): the frame's size, depth set-up
  // and samples, with an object-ID attachment.
  const gl::Framebuffer& idFramebuffer();
  gl::OracleFrame idPass(const Camera& camera);
  // The ID pass of a frame, from the shared cache when another runner did it.
  gl::OracleFrame visibleSet(std::optional<std::size_t> frame, const Camera& camera);
  FrameRecord render(const CameraPose& pose, std::size_t frame, bool cached);
  // The steps of a frame: a batch drawn (and recorded as drawn), the culler's batches
  // one after the other, and the check of what was drawn against the visible set.
  void drawBatch(const Camera& camera, const ObjectId* ids, std::size_t count, FrameRecord& rec);
  void cullAndDraw(const Camera& camera, FrameRecord& rec);
  void checkAgainst(const gl::OracleFrame& oracle, FrameRecord& rec);
  // How many objects these ids draw part of (clusters.hpp): distinct objectOf().
  std::size_t objectsOf(const std::vector<ObjectId>& ids);
  void writeImages(std::size_t frame, const Camera& camera);
  // The framebuffer of config_.view, then the reader and the query source over it
  // (constructor, setView).
  void makeFramebuffer();
  void makeSources();
  const Hierarchy& staticHierarchy() const {
    return static_override_ ? *static_override_ : scene_.hierarchy;
  }

  const PreparedScene& scene_;
  gl::MeshRenderer& renderer_;
  RunConfig config_;
  std::unique_ptr<gl::Framebuffer> framebuffer_;     // every timed frame's, never with IDs
  std::unique_ptr<gl::Framebuffer> id_framebuffer_;  // the ID pass's (idFramebuffer())
  std::unique_ptr<FrameReader> reader_;
  std::unique_ptr<OcclusionQueries> queries_;  // query methods
  std::unique_ptr<Culler> culler_;
  std::unique_ptr<Culler> vfc_;                   // for the ID pass
  std::unique_ptr<ddo::OccluderPass> occluders_;  // MethodNeeds::occluders
  struct Observer;
  std::unique_ptr<Observer> observer_;
  struct FanOut;
  std::unique_ptr<FanOut> fan_out_;
  std::unique_ptr<bvh::MotionHierarchy> dynamic_;  // null: the static hierarchy
  const Hierarchy* static_override_ = nullptr;     // setHierarchy()
  MotionFrame motion_;
  std::vector<std::uint8_t> drawn_;  // per object, this frame
  std::vector<ObjectId> drawn_list_;
  std::vector<ObjectId> facing_;  // a batch without its clusters facing away
  double snap_step_ = 1;          // GL's sub-pixel step, in pixels (clusterFacesAway)
  std::vector<ObjectId> missed_;
  std::shared_ptr<OracleCache> oracle_cache_;
};

}  // namespace logrid::samples
