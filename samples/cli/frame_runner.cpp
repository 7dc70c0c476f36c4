#include "cli/frame_runner.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "cli/images.hpp"
#include "logrid/error.hpp"
#include "logrid/gl/context.hpp"
#include "logrid/zread/gl_sources.hpp"

namespace logrid::samples {

std::string MethodChoice::name() const {
  std::string out = ddo == DdoUse::Culler      ? "ddo"
                    : ddo == DdoUse::Occluders ? "ddo+log"
                    : method                   ? toString(*method)
                                               : "oracle";
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
  if (parts[0] == "oracle" || parts[0] == "ddo") {
    if (parts.size() > 1) return std::nullopt;  // no logrid culler: no traversal settings
    if (parts[0] == "ddo") choice.ddo = DdoUse::Culler;
    return choice;
  }
  if (parts[0] == "ddo+log") {
    choice.method = Method::LogState;
    choice.ddo = DdoUse::Occluders;
  } else {
    const auto m = parseMethod(parts[0]);
    if (!m) return std::nullopt;
    choice.method = *m;
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
  fb.object_ids = config.verify || config.method.oracle();
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
  if (config.method.ddo != DdoUse::None) {
    if (!scene.ddo) {
      throw Error(ErrorCode::InvalidArgument,
                  "method " + config.method.name() +
                      " needs the scene's DDO octree (samples/scene/ddo_scene.hpp, prepareDdo)");
    }
    selector_ = std::make_unique<ddo::Selector>(*scene.ddo);
  }
  if (config.method.ddo == DdoUse::Occluders) {
    if (config.reader == "software") {
      throw Error(ErrorCode::InvalidArgument,
                  "method ddo+log draws its occluders with GL; use --reader readpixels, pbo or "
                  "query");
    }
    occluder_renderer_ = std::make_unique<gl::OccluderRenderer>();
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
  return makeCamera(scene_.path.frame(frame, config_.frames), scene_.origin, config_.view);
}

gl::OracleFrame FrameRunner::idPass(const Camera& camera) {
  return gl::objectIdOracle(*framebuffer_, camera, scene_.object_boxes, [&] {
    renderer_.begin(gl::Pass::ObjectIds, camera);
    vfc_->cullFrame(camera, scene_.hierarchy, g_no_depth, [&](ObjectId id) { renderer_.draw(id); });
    renderer_.end();
  });
}

gl::OracleFrame FrameRunner::visibleSet(std::size_t frame, const Camera& camera) {
  if (!oracle_cache_) return idPass(camera);
  auto& frames = oracle_cache_->frames;
  if (frames.size() <= frame) frames.resize(frame + 1);
  if (!frames[frame]) frames[frame] = idPass(camera);
  return *frames[frame];
}

FrameRecord FrameRunner::renderFrame(std::size_t frame) {
  FrameRecord rec;
  rec.frame = frame;
  const Camera camera = cameraFor(frame);
  gl::OracleFrame oracle;
  if (config_.method.oracle()) oracle = visibleSet(frame, camera);  // not timed
  for (ObjectId id : drawn_list_) drawn_[id] = 0;
  drawn_list_.clear();
  observer_->clear();

  glFinish();
  const auto start = std::chrono::steady_clock::now();
  framebuffer_->bind();
  framebuffer_->clear(kBackground);
  ddo::SelectionStats selection;
  if (config_.method.ddo == DdoUse::Occluders) {
    // Occluders first, into the depth buffer only; they are no object of the scene.
    selector_->select(camera, {}, selection, config_.culler.projection);
    occluder_renderer_->draw(selector_->occluders());
    rec.occluders = std::int64_t(selector_->occluders().size());
  }
  renderer_.begin(gl::Pass::Shaded, camera);
  auto draw = [&](ObjectId id) {
    renderer_.draw(id);
    rec.triangles += renderer_.triangles(id);
    if (!drawn_[id]) {
      drawn_[id] = 1;
      drawn_list_.push_back(id);
    }
    if (reader_) reader_->objectDrawn(id);
  };
  if (config_.method.oracle()) {
    for (ObjectId id : oracle.visible) draw(id);
    for (ObjectId id : oracle.artifacts) draw(id);  // the full render shows them
    rec.stats.objects_drawn = oracle.visible.size() + oracle.artifacts.size();
  } else if (config_.method.ddo == DdoUse::Culler) {
    selector_->select(camera, draw, selection, config_.culler.projection);
    rec.stats.nodes_visited = selection.nodes_visited;
    rec.stats.boxes_tested = selection.map_tests;
    rec.stats.boxes_occluded = selection.nodes_occluded;
    rec.stats.boxes_view_culled = selection.nodes_view_culled;
    rec.stats.boxes_near = selection.nodes_near;
    rec.stats.leaves_drawn = selection.leaves_visible;
    rec.stats.objects_drawn = selection.objects;
    rec.stats.seconds = selection.seconds;
    rec.occluders = std::int64_t(selection.faces_selected);
  } else {
    reader_->beginFrame(camera);
    // ddo+log: the occluders drawn above are announced, each with its pixels and its
    // farthest depth key, so that the grid reads those tiles and the occlusion-state order
    // knows how far back they lie.
    occluder_areas_.clear();
    if (selector_) {
      for (const ddo::Occluder& o : selector_->occluders()) {
        occluder_areas_.push_back({o.rect, o.far_key});
      }
    }
    rec.stats = culler_->cullFrame(camera, scene_.hierarchy, reader_->source(), draw,
                                   occluder_areas_);
    if (selector_) rec.stats.seconds += selection.seconds;
  }
  renderer_.end();
  glFinish();
  rec.ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  if (!config_.images_dir.empty()) writeImages(frame, camera);
  if (config_.verify || config_.method.oracle()) {
    if (!config_.method.oracle()) oracle = visibleSet(frame, camera);
    rec.visible = std::int64_t(oracle.visible.size());
    const std::vector<ObjectId> missed = oracle.missedBy(drawn_list_);
    rec.missed = std::int64_t(missed.size());
    rec.missed_ids.assign(missed.begin(),
                          missed.begin() + std::min<std::ptrdiff_t>(16, rec.missed));
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
  if (config_.overlay && selector_) {
    // The DDO occlusion map: pixels an occluder claims, tinted magenta over the frame.
    std::vector<std::uint8_t> tinted = color;
    const ddo::OcclusionMap& map = selector_->map();
    if (map.width() == camera.width && map.height() == camera.height) {
      const float clear = Projector(camera).clearKey();
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
    OverlayData overlay;
    overlay.grid = culler_->grid();
    overlay.occluded = observer_->occluded;
    overlay.tested_visible = observer_->tested_visible;
    for (NodeId n : observer_->drawn_nodes)
      overlay.drawn_boxes.push_back(scene_.hierarchy.bounds(n));
    writePng(std::string(stem) + "_overlay.png", drawOverlay(color, camera, overlay), camera.width,
             camera.height);
  }
}

}  // namespace logrid::samples
