#include "cli/frame_runner.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "logrid/error.hpp"
#include "logrid/gl/context.hpp"
#include "logrid/zread/gl_sources.hpp"

namespace logrid::samples {

std::string MethodChoice::name() const {
  std::string out = method ? toString(*method) : "oracle";
  if (lookahead) {
    out +=
        ":" + (*lookahead == kUnlimitedLookahead ? std::string("all") : std::to_string(*lookahead));
  }
  if (coherence) out += ":tc";
  return out;
}

std::optional<MethodChoice> parseMethodChoice(const std::string& name) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t colon; (colon = name.find(':', start)) != std::string::npos; start = colon + 1) {
    parts.push_back(name.substr(start, colon - start));
  }
  parts.push_back(name.substr(start));
  MethodChoice choice;
  if (parts[0] != "oracle") {
    const auto m = parseMethod(parts[0]);
    if (!m) return std::nullopt;
    choice.method = *m;
  } else if (parts.size() > 1) {
    return std::nullopt;  // the oracle takes no traversal settings
  }
  for (std::size_t i = 1; i < parts.size(); ++i) {
    if (parts[i] == "tc" && !choice.coherence) {
      choice.coherence = true;
    } else if (!choice.lookahead && !parts[i].empty() &&
               (parts[i] == "all" ||
                parts[i].find_first_not_of("0123456789") == std::string::npos)) {
      const unsigned long k = parts[i] == "all" ? kUnlimitedLookahead : std::stoul(parts[i]);
      if (k < 1 || k > kUnlimitedLookahead) return std::nullopt;
      choice.lookahead = std::uint32_t(k);
    } else {
      return std::nullopt;
    }
  }
  return choice;
}

namespace {

// For the ID pass: view-frustum culling never reads depth.
class NoDepthSource : public DepthSource {
 public:
  DepthSourceTraits traits() const override { return {"none", true, false}; }
  void beginFrame(const Camera&) override {}
  void submit(const AreaRequest*, std::size_t, AreaAnswer*) override { unused(); }
  void readKeys(const PixelRect&, float*) override { unused(); }

 private:
  [[noreturn]] static void unused() {
    throw Error(ErrorCode::Runtime, "internal: the ID pass read depth");
  }
};

NoDepthSource g_no_depth;

// Sky: a light blue-grey, distinct from every scene colour.
constexpr float kBackground[4] = {0.62f, 0.72f, 0.82f, 1.0f};

}  // namespace

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

FrameRunner::FrameRunner(const PreparedScene& scene, gl::MeshRenderer& renderer,
                         const RunConfig& config)
    : scene_(scene), renderer_(renderer), config_(config), observer_(std::make_unique<Observer>()) {
  if (config.frames == 0) throw Error(ErrorCode::InvalidArgument, "frames must be at least 1");
  gl::FramebufferDesc fb;
  fb.width = config.view.width;
  fb.height = config.view.height;
  fb.depth = config.view.depth;
  fb.samples = config.view.samples;
  fb.object_ids = config.verify || !config.method.method;
  framebuffer_ = std::make_unique<gl::Framebuffer>(fb);

  if (config.method.method) {
    CullerDesc desc = config.culler;
    desc.method = *config.method.method;
    culler_ = std::make_unique<Culler>(desc);
    if (config.overlay) culler_->setObserver(observer_.get());
    const ReaderInfo* reader = findReader(config.reader);
    if (!reader) {
      throw Error(ErrorCode::InvalidArgument,
                  "reader '" + config.reader + "' is unknown; use " + readerNames());
    }
    if (!reader->reads_depth && methodInfo(desc.method).needs_depth_values) {
      std::string readers;
      for (const ReaderInfo& r : readerTable()) {
        if (r.reads_depth) readers += std::string(readers.empty() ? "" : ", ") + r.name;
      }
      throw Error(ErrorCode::InvalidArgument, std::string("method ") + toString(desc.method) +
                                                  " needs depth values, which " + reader->name +
                                                  " cannot give; use --reader " + readers);
    }
    reader_ = reader->make({scene, framebuffer_->handle(), fb.width, fb.height, fb.depth});
  }
  CullerDesc vfc;
  vfc.method = Method::Vfc;
  vfc.projection = config.culler.projection;
  vfc_ = std::make_unique<Culler>(vfc);
  drawn_.assign(scene.mesh.draws.size(), 0);
  if (!config.images_dir.empty()) std::filesystem::create_directories(config.images_dir);
  gl::checkGlErrors("FrameRunner");
}

FrameRunner::~FrameRunner() = default;

Camera FrameRunner::cameraFor(std::size_t frame) const {
  return makeCamera(scene_.path.frame(frame, config_.frames, config_.span), scene_.origin,
                    config_.view);
}

gl::OracleFrame FrameRunner::idPass(const Camera& camera) {
  // A multisampled framebuffer gives one id and depth per sample: an object is visible
  // if any sample of it survives.
  return gl::objectIdOracle(*framebuffer_, camera, scene_.object_boxes, [&] {
    if (config_.hooks.after_clear) config_.hooks.after_clear();
    renderer_.begin(gl::Pass::ObjectIds, camera);
    vfc_->cullFrame(camera, scene_.hierarchy, g_no_depth, [&](ObjectId id) { renderer_.draw(id); });
    renderer_.end();
  });
}

gl::OracleFrame FrameRunner::visibleSet(std::optional<std::size_t> frame, const Camera& camera) {
  if (!oracle_cache_ || !frame) return idPass(camera);
  auto& frames = oracle_cache_->frames;
  if (frames.size() <= *frame) frames.resize(*frame + 1);
  if (!frames[*frame]) frames[*frame] = idPass(camera);
  return *frames[*frame];
}

FrameRecord FrameRunner::renderFrame(std::size_t frame) {
  return render(cameraFor(frame), frame, true);
}

FrameRecord FrameRunner::renderCamera(const Camera& camera, std::size_t frame) {
  if (camera.width != config_.view.width || camera.height != config_.view.height ||
      camera.depth.convention != config_.view.depth.convention ||
      camera.depth.format != config_.view.depth.format ||
      camera.depth.clip_range != config_.view.depth.clip_range) {
    throw Error(ErrorCode::InvalidArgument,
                "FrameRunner::renderCamera: the camera's viewport or depth set-up differs from "
                "the runner's view; make a runner for that view");
  }
  return render(camera, frame, false);
}

FrameRecord FrameRunner::render(const Camera& camera, std::size_t frame, bool cached) {
  FrameRecord rec;
  rec.frame = frame;
  const std::optional<std::size_t> cache_key =
      cached ? std::optional<std::size_t>(frame) : std::nullopt;
  gl::OracleFrame oracle;
  if (!config_.method.method) oracle = visibleSet(cache_key, camera);  // not timed
  for (ObjectId id : drawn_list_) drawn_[id] = 0;
  drawn_list_.clear();
  missed_.clear();
  observer_->clear();

  glFinish();
  const auto start = std::chrono::steady_clock::now();
  framebuffer_->bind();
  framebuffer_->clear(kBackground);
  if (config_.hooks.after_clear) config_.hooks.after_clear();
  renderer_.begin(gl::Pass::Shaded, camera);
  const FrameHooks& hooks = config_.hooks;
  auto draw = [&](ObjectId id) {
    if (hooks.before_draw) {
      hooks.before_draw();
      framebuffer_->bind();
      renderer_.begin(gl::Pass::Shaded, camera);
    }
    renderer_.draw(id);
    if (hooks.after_draw) hooks.after_draw();
    rec.triangles += renderer_.triangles(id);
    if (!drawn_[id]) {
      drawn_[id] = 1;
      drawn_list_.push_back(id);
    }
    if (reader_) reader_->objectDrawn(id);
  };
  if (!config_.method.method) {
    for (ObjectId id : oracle.visible) draw(id);
    for (ObjectId id : oracle.artifacts) draw(id);  // the full render shows them
    rec.stats.objects_drawn = oracle.visible.size() + oracle.artifacts.size();
  } else {
    reader_->beginFrame(camera);
    if (hooks.before_cull) hooks.before_cull();
    rec.stats = culler_->cullFrame(camera, scene_.hierarchy, reader_->source(), draw);
    if (hooks.after_cull) hooks.after_cull();
  }
  renderer_.end();
  glFinish();
  rec.ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  if (!config_.images_dir.empty()) writeImages(frame, camera);
  if (config_.verify || !config_.method.method) {
    if (config_.method.method) oracle = visibleSet(cache_key, camera);
    rec.visible = std::int64_t(oracle.visible.size());
    missed_ = oracle.missedBy(drawn_list_);
    rec.missed = std::int64_t(missed_.size());
    rec.missed_ids.assign(missed_.begin(),
                          missed_.begin() + std::min<std::ptrdiff_t>(16, rec.missed));
    rec.artifacts = std::int64_t(oracle.artifacts.size());
    rec.missed_artifacts = 0;
    for (ObjectId id : oracle.artifacts) rec.missed_artifacts += !drawn_[id];
  }
  gl::checkGlErrors("FrameRunner::renderFrame");
  return rec;
}

void FrameRunner::writeImages(std::size_t frame, const Camera& camera) {
  const std::vector<std::uint8_t> color = framebuffer_->readColor();
  char stem[512];
  std::snprintf(stem, sizeof stem, "%s/%s_%s_%04zu", config_.images_dir.c_str(),
                scene_.name.c_str(), config_.method.name().c_str(), frame);
  writePng(std::string(stem) + ".png", color, camera.width, camera.height);
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
  for (NodeId n : observer_->drawn_nodes) overlay.drawn_boxes.push_back(scene_.hierarchy.bounds(n));
  return overlay;
}

}  // namespace logrid::samples
