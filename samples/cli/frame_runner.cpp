#include "cli/frame_runner.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "logrid/error.hpp"
#include "logrid/gl/context.hpp"
#include "logrid/grid.hpp"
#include "logrid/zread/box_query_source.hpp"
#include "logrid/zread/calibration.hpp"
#include "logrid/zread/gl_sources.hpp"

namespace logrid::samples {

std::string MethodChoice::name() const {
  std::string out = method ? toString(*method) : "oracle";
  if (lookahead) {
    out +=
        ":" + (*lookahead == kUnlimitedLookahead ? std::string("all") : std::to_string(*lookahead));
  }
  if (coherence) out += ":tc";
  if (schedule) out += ":" + std::string(toString(*schedule));
  return out;
}

std::string methodChoiceHelp() {
  return methodNames() +
         " or oracle; a method may be followed by the settings it takes: :K or :all "
         "(lookahead), :tc (temporal coherence), and for log+hwq its query schedule (:" +
         querySchedules() + "), e.g. log-state:16:tc";
}

std::optional<MethodChoice> parseMethodChoice(const std::string& name, std::string* problem) {
  const auto refuse = [&](const std::string& why) -> std::optional<MethodChoice> {
    if (problem) *problem = "method '" + name + "': " + why;
    return std::nullopt;
  };
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t colon; (colon = name.find(':', start)) != std::string::npos; start = colon + 1) {
    parts.push_back(name.substr(start, colon - start));
  }
  parts.push_back(name.substr(start));
  MethodChoice choice;
  if (parts[0] == "oracle") {
    if (parts.size() > 1) return refuse("the oracle takes no settings");
    return choice;
  }
  const auto m = parseMethod(parts[0]);
  if (!m) return refuse("'" + parts[0] + "' is unknown; use " + methodChoiceHelp());
  choice.method = *m;
  const MethodTakes& takes = methodInfo(*m).takes;
  for (std::size_t i = 1; i < parts.size(); ++i) {
    const std::string& part = parts[i];
    const auto schedule = parseQuerySchedule(part);
    const bool count = !part.empty() &&
                       (part == "all" || part.find_first_not_of("0123456789") == std::string::npos);
    if (part == "tc" && takes.temporal_coherence && !choice.coherence) {
      choice.coherence = true;
    } else if (schedule && takes.query_schedule && !choice.schedule) {
      choice.schedule = *schedule;
    } else if (count && takes.lookahead && !choice.lookahead) {
      // Beyond any 32-bit count: refused before std::stoul could throw.
      const unsigned long k = part == "all"      ? kUnlimitedLookahead
                              : part.size() > 10 ? 0
                                                 : std::stoul(part);
      if (k < 1 || k > kUnlimitedLookahead) {
        return refuse("lookahead " + part + " is invalid; use 1 to " +
                      std::to_string(kUnlimitedLookahead) + " or all");
      }
      choice.lookahead = std::uint32_t(k);
    } else {
      std::string takes_list;
      if (takes.lookahead) takes_list += ":K or :all (lookahead)";
      if (takes.temporal_coherence)
        takes_list += std::string(takes_list.empty() ? "" : ", ") + ":tc";
      if (takes.query_schedule) {
        takes_list += std::string(takes_list.empty() ? "" : ", ") +
                      "a query schedule (:" + querySchedules() + ")";
      }
      return refuse("'" + part + "' is no setting " + parts[0] + " takes" +
                    (takes_list.empty() ? std::string(" (it takes none)")
                                        : "; it takes " + takes_list + ", each once"));
    }
  }
  return choice;
}

void measureHardwareIfNeeded(CullerDesc& desc) {
  if (querySchedule(desc) == QuerySchedule::Nohc &&
      !validateHardwareParameters(desc.queries.hardware).empty()) {
    desc.queries.hardware = zread::hardwareParameters();
  }
}

namespace {

// For the ID pass: view-frustum culling never reads depth.
class NoDepthSource : public DepthSource {
 public:
  DepthSourceTraits traits() const override { return {"none", true, false}; }
  Status beginFrame(const Camera&) override { return {}; }
  void submit(const AreaRequest*, std::size_t, AreaAnswer*) override { unused(); }

 private:
  [[noreturn]] static void unused() {
    throw Error(ErrorCode::Runtime, "internal: the ID pass read depth");
  }
};

NoDepthSource g_no_depth;

// Whether the culler begins and ends the reader's source: only for methods that read
// depth. For the others the runner does (render()).
bool sourceBegunByCuller(const RunConfig& config) {
  return methodInfo(*config.method.method).needs.depth;
}

// Sky: a light blue-grey, distinct from every scene colour.
constexpr float kBackground[4] = {0.62f, 0.72f, 0.82f, 1.0f};

}  // namespace

// Hands the culler's callbacks to several observers (the overlay's, the hierarchy's).
struct FrameRunner::FanOut : CullObserver {
  std::vector<CullObserver*> to;
  void onTested(NodeId node, const BoxProjection& p, Visibility v) override {
    for (CullObserver* o : to) o->onTested(node, p, v);
  }
  void onDrawn(NodeId node, const BoxProjection& p) override {
    for (CullObserver* o : to) o->onDrawn(node, p);
  }
};

// Collects what the overlay shows.
struct FrameRunner::Observer : CullObserver {
  std::vector<BoxProjection> occluded;
  std::vector<BoxProjection> tested_visible;
  std::vector<NodeId> drawn_nodes;
  void onTested(NodeId, const BoxProjection& p, Visibility v) override {
    (v == Visibility::Occluded ? occluded : tested_visible).push_back(p);
  }
  void onDrawn(NodeId node, const BoxProjection&) override { drawn_nodes.push_back(node); }
  void clear() {
    occluded.clear();
    tested_visible.clear();
    drawn_nodes.clear();
  }
};

namespace {

// What back-face culling asks of the rest of the run (RunConfig::backface_clusters,
// ViewSettings::cull_back_faces).
void checkFaceCulling(const RunConfig& config, const PreparedScene& scene) {
  if (config.backface_clusters) {
    if (!config.view.cull_back_faces) {
      throw Error(ErrorCode::InvalidArgument,
                  "--backface-clusters skips clusters that face away, which a renderer that "
                  "does not cull back faces still draws (a miss); add --cull-back-faces");
    }
    if (!scene.clustered()) {
      throw Error(ErrorCode::InvalidArgument,
                  "--backface-clusters needs a clustered scene; add --cluster N");
    }
    if (config.view.orthographic) {
      throw Error(ErrorCode::InvalidArgument,
                  "--backface-clusters needs a perspective view (the cone test is the eye's); "
                  "drop --ortho");
    }
  }
  if (config.view.cull_back_faces && config.method.method) {
    if (config.reader == "cpu" && methodInfo(*config.method.method).needs.depth) {
      throw Error(ErrorCode::InvalidArgument,
                  "--cull-back-faces with --reader cpu: the CPU occlusion buffer rasterises "
                  "both faces, and would hide what a back face culled by GL does not; use a "
                  "GL reader");
    }
    if (methodInfo(*config.method.method).needs.occluders) {
      throw Error(ErrorCode::InvalidArgument,
                  "--cull-back-faces with a DDO method: its occluders are found on geometry "
                  "drawn with both faces; use another method");
    }
  }
}

}  // namespace

FrameRunner::FrameRunner(const PreparedScene& scene, gl::MeshRenderer& renderer,
                         const RunConfig& config)
    : scene_(scene),
      renderer_(renderer),
      config_(config),
      observer_(std::make_unique<Observer>()),
      fan_out_(std::make_unique<FanOut>()) {
  if (config.frames == 0) throw Error(ErrorCode::InvalidArgument, "frames must be at least 1");
  if (!(config.time_step >= 0) || !std::isfinite(config.time_step)) {
    throw Error(ErrorCode::InvalidArgument, "time step " + std::to_string(config.time_step) +
                                                " is invalid; use 0 (frames spread over the "
                                                "path) or a positive number of seconds");
  }
  checkFaceCulling(config, scene);
  GLint subpixel_bits = 0;  // GL guarantees 4 or more
  glGetIntegerv(GL_SUBPIXEL_BITS, &subpixel_bits);
  snap_step_ = std::ldexp(1.0, -std::clamp(int(subpixel_bits), 0, 30));
  // Every object's box, the movers' where they are at the first frame; the motion
  // hierarchy is built over them.
  motion_.boxes = scene.object_boxes;
  applyMotion(frameTime(0));
  motion_.moved.clear();
  const std::string& h = config.hierarchy;
  if (!config.method.method) {
    // The oracle draws the visible set itself and walks no hierarchy.
  } else if (h == "static" || (h == "auto" && scene.motion.empty())) {
    if (!scene.motion.empty()) {
      throw Error(ErrorCode::InvalidArgument,
                  "the scene has " + std::to_string(scene.motion.movers.size()) +
                      " moving objects, which its static hierarchy does not hold; use "
                      "--hierarchy " +
                      bvh::motionNames());
    }
  } else {
    const auto kind = h == "auto" ? std::optional(bvh::MotionKind::Refit) : bvh::parseMotionKind(h);
    if (!kind) {
      throw Error(ErrorCode::InvalidArgument,
                  "hierarchy '" + h + "' is unknown; use auto, static, " + bvh::motionNames());
    }
    dynamic_ = bvh::makeMotionHierarchy(*kind, motion_.boxes, config.motion);
  }
  makeFramebuffer();
  if (config.method.method) {
    CullerDesc desc = config.culler;
    desc.method = *config.method.method;
    measureHardwareIfNeeded(desc);
    culler_ = std::make_unique<Culler>(desc);
    config_.culler.queries.hardware = desc.queries.hardware;
    if (config.overlay) fan_out_->to.push_back(observer_.get());
    if (dynamic_ && dynamic_->observer()) fan_out_->to.push_back(dynamic_->observer());
    if (!fan_out_->to.empty()) culler_->setObserver(fan_out_.get());
  }
  makeSources();
  if (config.method.method && methodInfo(*config.method.method).needs.occluders) {
    const MethodInfo& info = methodInfo(*config.method.method);
    if (!scene.ddo) {
      throw Error(ErrorCode::InvalidArgument,
                  std::string("method ") + info.name +
                      " needs the scene's DDO octree, which is prepared when the command's "
                      "--method names a method that needs it (samples/scene/ddo_scene.hpp)");
    }
    ddo::OccluderBudget budget;
    budget.tile_size = config.culler.tile_size;  // count the tiles of the grid that records them
    // ddo+log records its occluders without drawing them, and needs no map: the map's
    // clear and rasterisation cost more than the octree nodes it culls (office 0.35:
    // 0.42 against 0.07 ms a frame, city 0.1: 1.48 against 1.25 ms; docs/DDO.md).
    ddo::SelectorSettings selection;
    selection.occlusion_map = info.occluders == OccluderUse::Map;
    if (info.occluders == OccluderUse::Recorded) selection.min_node_pixels = budget.tile_size;
    occluders_ = std::make_unique<ddo::OccluderPass>(*scene.ddo, ddo::OccluderPass::Drawer{},
                                                     selection, budget);
  }
  CullerDesc vfc;  // the ID pass's: the default (safe) projection settings, as the oracle's
  vfc.method = Method::Vfc;
  vfc_ = std::make_unique<Culler>(vfc);
  drawn_.assign(scene.mesh.draws.size(), 0);
  if (!config.images_dir.empty()) std::filesystem::create_directories(config.images_dir);
  gl::checkGlErrors("FrameRunner");
}

FrameRunner::~FrameRunner() = default;

void FrameRunner::makeFramebuffer() {
  const RunConfig& config = config_;
  gl::FramebufferDesc fb;
  fb.width = config.view.width;
  fb.height = config.view.height;
  fb.depth = config.view.depth;
  fb.samples = config.view.samples;
  // Every row's frames, the oracle's included, verified or not, go into the same kind of
  // framebuffer: colour and depth only. The ID pass has its own (idFramebuffer()): an ID
  // attachment bound during a timed frame slowed it (its clear after an ID pass cost
  // llvmpipe 10-19 ms at 640x480), which made a verified frame and the oracle's slower
  // than the same frame unverified (docs/ANALYSIS.md, "An honest floor").
  fb.object_ids = false;
  reader_.reset();  // readers and queries hold the old framebuffer's handle
  queries_.reset();
  id_framebuffer_.reset();
  framebuffer_ = std::make_unique<gl::Framebuffer>(fb);
}

const gl::Framebuffer& FrameRunner::idFramebuffer() {
  if (!id_framebuffer_) {
    gl::FramebufferDesc ids = framebuffer_->desc();
    ids.object_ids = true;
    id_framebuffer_ = std::make_unique<gl::Framebuffer>(ids);
  }
  return *id_framebuffer_;
}

void FrameRunner::makeSources() {
  const RunConfig& config = config_;
  if (!config.method.method) return;
  const gl::FramebufferDesc& fb = framebuffer_->desc();
  const MethodInfo& info = methodInfo(*config.method.method);
  if (info.needs.queries) {
    queries_ = std::make_unique<zread::BoxQuerySource>(
        framebuffer_->handle(), config.any_samples_passed
                                    ? zread::QueryTarget::AnySamplesPassedConservative
                                    : zread::QueryTarget::SamplesPassed);
  }
  const ReaderInfo* reader = findReader(config.reader);
  if (!reader) {
    throw Error(ErrorCode::InvalidArgument,
                "reader '" + config.reader + "' is unknown; use " + readerNames());
  }
  const auto readersThat = [](bool ReaderInfo::*what) {
    std::string readers;
    for (const ReaderInfo& r : readerTable()) {
      if (r.*what) readers += std::string(readers.empty() ? "" : ", ") + r.name;
    }
    return readers;
  };
  if (!reader->reads_depth && info.needs.depth_values) {
    throw Error(ErrorCode::InvalidArgument,
                std::string("method ") + info.name + " needs depth values, which " + reader->name +
                    " cannot give; use --reader " + readersThat(&ReaderInfo::reads_depth));
  }
  reader_ = reader->make({scene_, framebuffer_->handle(), fb.width, fb.height, fb.depth, &motion_,
                          &config.cpu, config.culler.projection, info.method});
}

void FrameRunner::setView(const ViewSettings& view) {
  RunConfig next = config_;
  next.view = view;
  checkFaceCulling(next, scene_);
  config_.view = view;
  oracle_cache_.reset();  // its ID passes were of the old view
  makeFramebuffer();
  makeSources();
  gl::checkGlErrors("FrameRunner::setView");
}

void FrameRunner::setHierarchy(const Hierarchy* hierarchy) {
  if (dynamic_ || !culler_) {
    throw Error(ErrorCode::InvalidArgument,
                "FrameRunner::setHierarchy: only a runner that culls the scene's static "
                "hierarchy can be given another");
  }
  static_override_ = hierarchy;
  oracle_cache_.reset();  // its ID passes drew the old hierarchy's objects
}

double FrameRunner::frameTime(std::size_t frame) const {
  if (config_.time_step > 0 && !scene_.path.empty()) {
    return scene_.path.keys().front().time + double(frame) * config_.time_step;
  }
  return scene_.path.frameTime(frame, config_.frames);
}

CameraPose FrameRunner::poseFor(std::size_t frame) const {
  return scene_.path.at(frameTime(frame));
}

Camera FrameRunner::cameraFor(std::size_t frame) const { return cameraAt(poseFor(frame)); }

Camera FrameRunner::cameraAt(const CameraPose& pose) const {
  return makeCamera(pose, scene_.origin, config_.view);
}

const Hierarchy& FrameRunner::hierarchy() const {
  return dynamic_ ? static_cast<const Hierarchy&>(*dynamic_) : staticHierarchy();
}

void FrameRunner::applyMotion(double time) {
  if (scene_.motion.empty()) {
    motion_.time = time;
    motion_.moved.clear();
    return;
  }
  evaluateMotion(scene_.motion, scene_.static_objects, time, motion_);
  // The renderer is shared by every runner of a scene: set the transforms each frame.
  for (std::size_t i = 0; i < motion_.transforms.size(); ++i) {
    const RigidTransform& r = motion_.transforms[i];
    gl::ObjectTransform t;
    for (int k = 0; k < 9; ++k) t.rotation[k] = static_cast<float>(r.rotation[k]);
    t.translation = r.translation;
    renderer_.setTransform(scene_.static_objects + static_cast<ObjectId>(i), t);
  }
}

gl::OracleFrame FrameRunner::idPass(const Camera& camera) {
  // Boxes at the frame's time: the movers' own (not from any hierarchy under test).
  // A multisampled framebuffer gives one id and depth per sample: an object is visible
  // if any sample of it survives. Never inside a timed frame: before it (the oracle's
  // visible set) or after it (verification).
  // One projector for the pass: the oracle judges with it, and the movers are
  // frustum-culled with it. The oracle needs the default settings; the ID pass's culler
  // (vfc_) projects with them too, whatever the method under test is given.
  const Projector projector(camera);
  gl::OracleFrame found = gl::objectIdOracle(idFramebuffer(), projector, motion_.boxes, [&] {
    if (config_.hooks.after_clear) config_.hooks.after_clear();
    renderer_.setCullBackFaces(config_.view.cull_back_faces);  // the frames' picture
    renderer_.begin(gl::Pass::ObjectIds, camera);
    vfc_->cullFrame(camera, staticHierarchy(), g_no_depth,
                    [&](ObjectId id) { renderer_.draw(id); });
    // The movers, from their own boxes at the frame's time.
    for (ObjectId id = scene_.static_objects; id < motion_.boxes.size(); ++id) {
      if (projector.project(motion_.boxes[id]).cls != ProjectionClass::Outside) renderer_.draw(id);
    }
    renderer_.end();
  });
  framebuffer_->bind();  // the frame's framebuffer stays the bound one, as after a frame
  return found;
}

gl::OracleFrame FrameRunner::visibleSet(std::optional<std::size_t> frame, const Camera& camera) {
  if (!oracle_cache_ || !frame) return idPass(camera);
  auto& frames = oracle_cache_->frames;
  if (frames.size() <= *frame) frames.resize(*frame + 1);
  if (!frames[*frame]) frames[*frame] = idPass(camera);
  return *frames[*frame];
}

FrameRecord FrameRunner::renderFrame(std::size_t frame) {
  return render(poseFor(frame), frame, true);
}

FrameRecord FrameRunner::renderPose(const CameraPose& pose, std::size_t frame) {
  return render(pose, frame, false);
}

FrameRecord FrameRunner::render(const CameraPose& pose, std::size_t frame, bool cached) {
  FrameRecord rec;
  rec.frame = frame;
  const std::optional<std::size_t> cache_key =
      cached ? std::optional<std::size_t>(frame) : std::nullopt;
  rec.time = frameTime(frame);
  applyMotion(rec.time);
  rec.moved = motion_.moved.size();
  const Camera camera = cameraAt(pose);
  gl::OracleFrame oracle;
  if (config_.method.oracle()) oracle = visibleSet(cache_key, camera);  // not timed
  for (ObjectId id : drawn_list_) drawn_[id] = 0;
  drawn_list_.clear();
  missed_.clear();
  observer_->clear();

  glFinish();
  const auto start = std::chrono::steady_clock::now();
  const std::uint64_t draw_calls = renderer_.drawCalls();
  if (dynamic_) {
    bvh::MotionUpdate update;
    update.boxes = &motion_.boxes;
    update.moved = &motion_.moved;
    update.view_direction = {pose.look_at.x - pose.position.x, pose.look_at.y - pose.position.y,
                             pose.look_at.z - pose.position.z};
    rec.update = dynamic_->update(update);
  }
  framebuffer_->bind();
  framebuffer_->unmask();  // after a reader that leaves its state (leavesGlState)
  framebuffer_->clear(kBackground);
  if (config_.hooks.after_clear) config_.hooks.after_clear();
  renderer_.setCullBackFaces(config_.view.cull_back_faces);  // shared by the scene's runners
  renderer_.begin(gl::Pass::Shaded, camera);
  if (config_.method.oracle()) {
    // The visible set as one batch, drawn as a method's batches are.
    std::vector<ObjectId> all = oracle.visible;
    all.insert(all.end(), oracle.artifacts.begin(), oracle.artifacts.end());  // the full
    drawBatch(camera, all.data(), all.size(), rec);                           // render shows them
    rec.stats.objects_drawn = all.size();
  } else {
    cullAndDraw(camera, rec);
  }
  renderer_.end();
  // The hierarchy's statistics of this frame (ternary: the additional queries).
  if (dynamic_ && culler_) rec.measure = dynamic_->measure(camera, reader_->source());
  if (culler_ && !sourceBegunByCuller(config_)) orThrow(reader_->source().endFrame());
  glFinish();
  rec.ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (culler_) culler_->reportFrameTime(rec.ms * 1e-3);  // the whole frame (frame_clock)
  rec.draw_calls = renderer_.drawCalls() - draw_calls;
  if (scene_.clustered()) rec.objects_drawn = std::int64_t(objectsOf(drawn_list_));

  if (!config_.images_dir.empty()) writeImages(frame, camera);
  if (config_.verify || config_.method.oracle()) {
    if (!config_.method.oracle()) oracle = visibleSet(cache_key, camera);
    checkAgainst(oracle, rec);
  }
  gl::checkGlErrors("FrameRunner::renderFrame");
  return rec;
}

void FrameRunner::drawBatch(const Camera& camera, const ObjectId* ids, std::size_t count,
                            FrameRecord& rec) {
  if (config_.backface_clusters) {
    // The clusters facing away are not drawn (GL would cull every triangle of them).
    facing_.clear();
    for (std::size_t i = 0; i < count; ++i) {
      const ObjectId id = ids[i];
      if (clusterFacesAway(scene_, motion_, id, camera, camera.render_origin, snap_step_)) {
        ++rec.backfacing;
      } else {
        facing_.push_back(id);
      }
    }
    ids = facing_.data();
    count = facing_.size();
  }
  const FrameHooks& hooks = config_.hooks;
  if (hooks.before_draw) {
    // An application with state of its own between its draws: one call each.
    for (std::size_t i = 0; i < count; ++i) {
      hooks.before_draw();
      framebuffer_->bind();
      renderer_.begin(gl::Pass::Shaded, camera);
      renderer_.draw(ids[i]);
      if (hooks.after_draw) hooks.after_draw();
    }
  } else {
    renderer_.drawBatch(ids, count);
    if (hooks.after_draw) hooks.after_draw();
  }
  for (std::size_t i = 0; i < count; ++i) {
    const ObjectId id = ids[i];
    rec.triangles += renderer_.triangles(id);
    if (!drawn_[id]) {
      drawn_[id] = 1;
      drawn_list_.push_back(id);
    }
    if (reader_) reader_->objectDrawn(id);
  }
}

void FrameRunner::cullAndDraw(const Camera& camera, FrameRecord& rec) {
  reader_->beginFrame(camera);
  // A method that reads no depth leaves the reader's source alone, but the runner still
  // feeds it what is drawn (objectDrawn: the cpu reader's buffer) and the motion
  // hierarchy's statistics pass reads it (measure): its frame is begun here instead.
  if (!sourceBegunByCuller(config_)) orThrow(reader_->source().beginFrame(camera));
  if (config_.hooks.before_cull) config_.hooks.before_cull();
  // The pull form (the callback form is a loop over it): each batch drawn, then the next.
  culler_->beginFrame(camera, hierarchy(), {&reader_->source(), queries_.get(), occluders_.get()});
  try {
    for (DrawBatch batch = culler_->nextBatch(); !batch.empty(); batch = culler_->nextBatch()) {
      if (reader_->leavesGlState()) {
        // Under GlStatePolicy::ApplicationManaged the source's passes leave their state
        // (a multisample resolve: its framebuffer, program and vertex array, whose
        // missing element buffer crashed the driver, the scissor and colour masks):
        // the application sets what it draws with.
        framebuffer_->bind();
        framebuffer_->unmask();
        renderer_.begin(gl::Pass::Shaded, camera);
      }
      drawBatch(camera, batch.begin(), batch.size(), rec);
    }
  } catch (...) {
    culler_->abandonFrame();  // a draw failed: the runner stays usable (the viewer goes on)
    if (!sourceBegunByCuller(config_)) (void)reader_->source().endFrame();
    throw;
  }
  rec.stats = culler_->endFrame();
  if (occluders_) rec.occluders = std::int64_t(rec.stats.occluders);
  if (auto* cpu = dynamic_cast<CpuFrameReader*>(reader_.get())) rec.cpu = cpu->takeFrameStats();
  if (config_.hooks.after_cull) config_.hooks.after_cull();
}

void FrameRunner::checkAgainst(const gl::OracleFrame& oracle, FrameRecord& rec) {
  rec.visible = std::int64_t(oracle.visible.size());
  if (scene_.clustered()) rec.visible_objects = std::int64_t(objectsOf(oracle.visible));
  missed_ = oracle.missedBy(drawn_list_);
  rec.missed = std::int64_t(missed_.size());
  rec.missed_ids.assign(missed_.begin(),
                        missed_.begin() + std::min<std::ptrdiff_t>(16, rec.missed));
  rec.artifacts = std::int64_t(oracle.artifacts.size());
  rec.missed_artifacts = 0;
  for (ObjectId id : oracle.artifacts) rec.missed_artifacts += !drawn_[id];
}

std::size_t FrameRunner::objectsOf(const std::vector<ObjectId>& ids) {
  std::vector<std::uint32_t> objects;
  objects.reserve(ids.size());
  for (ObjectId id : ids) objects.push_back(scene_.objectOf(id));
  std::sort(objects.begin(), objects.end());
  return std::size_t(std::unique(objects.begin(), objects.end()) - objects.begin());
}

void FrameRunner::writeImages(std::size_t frame, const Camera& camera) {
  const std::vector<std::uint8_t> color = framebuffer_->readColor();
  char stem[512];
  std::snprintf(stem, sizeof stem, "%s/%s_%s_%04zu", config_.images_dir.c_str(),
                scene_.name.c_str(), config_.method.name().c_str(), frame);
  writePng(std::string(stem) + ".png", color, camera.width, camera.height);
  if (config_.overlay && occluders_) {
    // The DDO occlusion map: pixels an occluder claims, tinted magenta over the frame.
    std::vector<std::uint8_t> tinted = color;
    const ddo::OcclusionMap& map = occluders_->selector().map();
    if (map.width() == camera.width && map.height() == camera.height) {
      const float clear = clearKey(camera.depth);
      for (std::uint32_t y = 0; y < camera.height; ++y) {
        for (std::uint32_t x = 0; x < camera.width; ++x) {
          if (!(map.key(x, y) < clear)) continue;
          std::uint8_t* p = &tinted[(std::size_t(y) * camera.width + x) * 4];
          p[0] = std::uint8_t((p[0] + 255) / 2), p[1] = std::uint8_t(p[1] / 2);
          p[2] = std::uint8_t((p[2] + 255) / 2);
        }
      }
    }
    writePng(std::string(stem) + "_ddo_map.png", tinted, camera.width, camera.height);
  }
  if (config_.overlay && culler_) {
    writePng(std::string(stem) + "_overlay.png", drawOverlay(color, camera, overlayData()),
             camera.width, camera.height);
  }
}

OverlayData FrameRunner::overlayData() const {
  OverlayData overlay;
  if (!culler_) return overlay;
  overlay.grid = culler_->grid();
  overlay.occluded = observer_->occluded;
  overlay.tested_visible = observer_->tested_visible;
  for (NodeId n : observer_->drawn_nodes) overlay.drawn_boxes.push_back(hierarchy().bounds(n));
  return overlay;
}

}  // namespace logrid::samples
