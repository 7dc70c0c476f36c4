// What the oracle tests share: procedural scenes loaded once per process (optionally
// moved far from the world origin, with moving objects, with a DDO octree), a run
// configuration built from a few named fields, a walk that checks every frame against the
// object-ID pass of FrameRunner, and the one harness of the walk, motion and DDO oracle
// tests: an OracleCase in (scene, method with its settings, reader, view, frames, what
// the walk must show), checkCase() asserts zero misses and that the walk tests something.
//
// The oracle (docs/DESIGN.md, "The oracle"): after each frame FrameRunner draws the
// whole frustum-culled scene into an R32UI ID buffer with the same renderer and the same
// camera; every ID found there is a visible object and must have been drawn by the
// method under test. A miss is reported with the frame, the camera, the object's box and
// (where one exists) a `logrid walk` command line that reproduces it.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <string>

#include "cli/frame_runner.hpp"
#include "gl_test_context.hpp"
#include "logrid/gl/mesh_renderer.hpp"
#include "scene/ddo_scene.hpp"
#include "scene/generators.hpp"
#include "scene/loader.hpp"
#include "scene/movers.hpp"
#include "scene/obj_writer.hpp"
#include "scene/prepare.hpp"
#include "scene/view.hpp"

namespace logrid::oracle {

using samples::FrameRecord;
using samples::FrameRunner;
using samples::PreparedScene;
using samples::RunConfig;

// Scales small enough for a 2-core CI machine and large enough to occlude: the forest at
// 0.1 has 492 objects (134k triangles), the city at 0.01 has 256 chunks (266k triangles).
inline constexpr double kForestScale = 0.1;
inline constexpr double kCityScale = 0.01;
// "office-file": the office generator at this scale written as OBJ and read back through
// the model loader (closed, finely tessellated walls and slabs; 4 rooms on each side of
// each corridor).
inline constexpr double kOfficeScale = 0.35;

// How a scene is moved away from the world origin.
enum class Offset : std::uint8_t {
  None,
  // Scene::origin: the geometry stays local (float, near zero) and the cameras compose
  // the translation in double; the renderer draws camera-relative. The designed way.
  Origin,
  // The float vertex positions themselves are moved (an application that stores world
  // coordinates in float); Scene::origin stays 0, Camera::render_origin becomes the eye.
  FloatPositions,
};

inline const char* toString(Offset o) {
  switch (o) {
    case Offset::None: return "none";
    case Offset::Origin: return "origin";
    case Offset::FloatPositions: return "float_positions";
  }
  return "?";
}

struct SceneKey {
  std::string name;  // forest, city, office or office-file
  double scale = kForestScale;
  Offset offset = Offset::None;
  double distance = 0;        // added to x, y and z (world units)
  std::uint32_t movers = 0;   // moving objects (samples/scene/movers.hpp, seed 1)
  bool ddo = false;           // with its DDO octree (ddoOptions(), built in memory)
  std::uint32_t cluster = 0;  // triangles per cluster (samples/scene/clusters.hpp); 0: whole

  std::string id() const {
    std::ostringstream out;
    out << name << "@" << scale << "/" << toString(offset) << "/" << distance << "/" << movers
        << (ddo ? "/ddo" : "") << (cluster ? "/cluster" + std::to_string(cluster) : "");
    return out.str();
  }
};

// The scene of a name at the tests' scale: forest, city, office or office-file.
inline SceneKey sceneKey(const std::string& name, std::uint32_t movers = 0, bool ddo = false) {
  SceneKey k;
  k.name = name;
  k.scale = name == "city"                              ? kCityScale
            : name == "office" || name == "office-file" ? kOfficeScale
                                                        : kForestScale;
  k.movers = movers;
  k.ddo = ddo;
  return k;
}

// The DDO of the tests: 32 regions (the unit tests cover both layouts), built in memory.
inline samples::DdoOptions ddoOptions() {
  samples::DdoOptions d;
  d.regions = 32;
  d.threads = 2;
  d.progress = false;
  return d;
}

struct LoadedScene {
  PreparedScene prepared;
  std::unique_ptr<gl::MeshRenderer> renderer;
};

// Moves a generated scene (and its camera path, which is in world coordinates) by
// `distance` on every axis.
inline void offsetScene(samples::Scene& scene, Offset offset, double distance) {
  if (offset == Offset::None) return;
  std::vector<samples::CameraKey> keys = scene.path.keys();
  for (samples::CameraKey& k : keys) {
    k.position = {k.position.x + distance, k.position.y + distance, k.position.z + distance};
    k.look_at = {k.look_at.x + distance, k.look_at.y + distance, k.look_at.z + distance};
  }
  scene.path = samples::CameraPath(std::move(keys));
  if (offset == Offset::Origin) {
    scene.origin = {scene.origin.x + distance, scene.origin.y + distance,
                    scene.origin.z + distance};
  } else {
    for (float& p : scene.positions) p = static_cast<float>(double(p) + distance);
    samples::computeBounds(scene);  // object boxes from the rounded positions
  }
}

// The office generator written as OBJ, then read back through the model loader.
inline samples::Scene officeFromFile(double scale) {
  samples::Scene generated = samples::makeOffice({scale, 1});
  const std::string file =
      testing::TempDir() + "logrid_oracle_office_" + std::to_string(getpid()) + ".obj";
  samples::writeObj(generated, file);
  samples::Scene scene = samples::loadSceneFile(file);
  std::remove(file.c_str());
  scene.path = generated.path;
  scene.near_plane = generated.near_plane;
  scene.far_plane = generated.far_plane;
  return scene;
}

// The scene for a key, generated, prepared and uploaded once per process. Needs a
// current context (call LOGRID_REQUIRE_GL() first).
inline LoadedScene& loadScene(const SceneKey& key) {
  static std::map<std::string, std::unique_ptr<LoadedScene>> cache;
  std::unique_ptr<LoadedScene>& slot = cache[key.id()];
  if (!slot) {
    samples::Scene scene = key.name == "city"          ? samples::makeCity({key.scale, 1})
                           : key.name == "office"      ? samples::makeOffice({key.scale, 1})
                           : key.name == "office-file" ? officeFromFile(key.scale)
                                                       : samples::makeForest({key.scale, 1});
    offsetScene(scene, key.offset, key.distance);
    samples::addMovers(scene, key.movers, 1);
    const bvh::BuildArgs args = samples::defaultBuildArgs(scene);
    slot = std::make_unique<LoadedScene>();
    samples::ClusterOptions clusters;
    clusters.triangles = key.cluster;
    slot->prepared = samples::prepareScene(std::move(scene), args, clusters);
    if (key.ddo) slot->prepared.ddo = samples::prepareDdo(slot->prepared, ddoOptions()).octree;
    slot->renderer = std::make_unique<gl::MeshRenderer>(slot->prepared.mesh);
  }
  return *slot;
}

// Frames for a walk: `n` times LOGRID_ORACLE_INTENSITY (default 1), so that a soak run
// (LOGRID_ORACLE_INTENSITY=20 ./oracle_test) checks many more camera poses than CI does.
inline std::size_t intensityFrames(std::size_t n) {
  const char* v = std::getenv("LOGRID_ORACLE_INTENSITY");
  const long k = v ? std::strtol(v, nullptr, 10) : 1;
  return n * std::size_t(k > 1 ? k : 1);
}

inline const char* formatName(DepthFormat f) {
  switch (f) {
    case DepthFormat::D16: return "16";
    case DepthFormat::D24: return "24";
    case DepthFormat::D32F: return "32f";
  }
  return "?";
}

// One run's settings; the scene's own clip planes where near/far are 0.
struct View {
  std::uint32_t width = 160;
  std::uint32_t height = 120;
  std::uint32_t tile = 32;
  DepthConvention convention = DepthConvention::Standard;
  DepthFormat format = DepthFormat::D32F;
  double near_plane = 0;
  double far_plane = 0;
  double fov = 60;
  bool ortho = false;
  bool cull_back_faces = false;  // ViewSettings::cull_back_faces
};

inline RunConfig makeConfig(const PreparedScene& scene, Method method, const std::string& reader,
                            const View& v, std::size_t frames) {
  RunConfig c;
  c.method.method = method;
  c.culler.tile_size = v.tile;
  c.reader = reader;
  c.view.width = v.width;
  c.view.height = v.height;
  c.view.fov_degrees = v.fov;
  c.view.orthographic = v.ortho;
  c.view.near_plane = v.near_plane > 0 ? v.near_plane : scene.near_plane;
  c.view.far_plane = v.far_plane > 0 ? v.far_plane : scene.far_plane;
  c.view.depth = samples::depthSetupFor(v.convention, v.format);
  c.view.cull_back_faces = v.cull_back_faces;
  c.frames = intensityFrames(frames);
  c.verify = true;
  return c;
}

// The command line that replays a run, for runs the CLI can express.
inline std::string reproducer(const SceneKey& key, const RunConfig& c) {
  std::ostringstream out;
  if (key.offset != Offset::None) {
    out << "(no CLI equivalent: scene moved by " << key.distance << " via " << toString(key.offset)
        << "; run this test) ";
  }
  if (key.name == "office-file") {
    out << "logrid export --scene office --scale " << key.scale
        << " --obj office.obj --path-json office.json && logrid walk --scene office.obj --path "
           "office.json";
  } else {
    out << "logrid walk --scene " << key.name << " --scale " << key.scale;
  }
  if (key.ddo) out << " --ddo-regions 32";
  if (key.cluster) out << " --cluster " << key.cluster;
  if (key.movers) {
    out << " --movers " << key.movers << " --hierarchy " << c.hierarchy;
    if (c.time_step > 0) out << " --time-step " << c.time_step;
    if (c.culler.lookahead != 1) {
      out << " --lookahead "
          << (c.culler.lookahead == kUnlimitedLookahead ? std::string("all")
                                                        : std::to_string(c.culler.lookahead));
    }
    if (c.culler.detect_colliding) out << " --colliding";
    if (c.culler.temporal_coherence) out << " --coherence";
  }
  out << " --frames " << c.frames << " --method " << c.method.name() << " --reader " << c.reader
      << " --size " << c.view.width << "x" << c.view.height << " --tile " << c.culler.tile_size
      << " --depth-format " << formatName(c.view.depth.format) << " --depth-convention "
      << toString(c.view.depth.convention) << " --near " << c.view.near_plane << " --far "
      << c.view.far_plane;
  if (c.view.samples > 1) out << " --samples " << c.view.samples;
  if (c.view.cull_back_faces) out << " --cull-back-faces";
  if (c.backface_clusters) out << " --backface-clusters";
  if (c.view.orthographic) {
    out << " --ortho";
  } else {
    out << " --fov " << c.view.fov_degrees;
  }
  if (c.reader == "cpu") {
    out << " --cpu-resolution " << cpu::toString(c.cpu.resolution) << " --cpu-buffer "
        << cpu::toString(c.cpu.representation) << " --occluders "
        << samples::toString(c.cpu.occluders) << " --cpu-threads " << c.cpu.threads
        << " --occluder-pixels " << c.cpu.min_pixels_per_triangle << " --occluder-budget "
        << c.cpu.triangle_budget;
  }
  out << " --verify";
  return out.str();
}

inline bool finiteStats(const FrameRecord& r) {
  const FrameStats& s = r.stats;
  return std::isfinite(r.ms) && r.ms >= 0 && std::isfinite(s.seconds) && s.seconds >= 0 &&
         std::isfinite(s.read_seconds) && s.read_seconds >= 0 && std::isfinite(s.tilesPerBox());
}

// What a walk did, summed over its frames.
struct WalkTotals {
  std::size_t frames = 0;
  std::uint64_t visible = 0;
  std::uint64_t missed = 0;
  std::uint64_t artifacts = 0;       // objects shown only by depth-extrapolated fragments
  std::uint64_t drawn = 0;           // objects drawn (draw callbacks)
  std::uint64_t occluded = 0;        // boxes found occluded
  std::uint64_t tested = 0;          // occlusion tests
  std::uint64_t invalid = 0;         // boxes the culler found NaN or inverted
  std::uint64_t occluders = 0;       // DDO occluders drawn or entered into the map
  std::uint64_t occluder_tiles = 0;  // ddo+log: tiles recorded full from their coverage
  std::uint64_t backfacing = 0;      // clusters not drawn for facing away
  std::uint64_t cpu_moved = 0;       // --reader cpu: moving objects drawn into its buffer
  double ms = 0;
};

// Renders every frame of a walk with the oracle check and asserts, per frame: the oracle
// ran, no visible object was missed (else: frame, camera, the missed objects' boxes and a
// command line), and no time is NaN or negative.
inline WalkTotals checkedWalk(const SceneKey& key, LoadedScene& scene, const RunConfig& config) {
  WalkTotals t;
  FrameRunner runner(scene.prepared, *scene.renderer, config);
  for (std::size_t f = 0; f < config.frames; ++f) {
    const FrameRecord r = runner.renderFrame(f);
    ++t.frames;
    EXPECT_GE(r.visible, 0) << "the oracle did not run for frame " << f;
    EXPECT_EQ(r.missed, 0) << [&] {
      std::ostringstream out;
      out.precision(12);
      const Camera cam = runner.cameraFor(f);
      const samples::CameraPose pose = runner.poseFor(f);
      out << config.method.name() << " missed " << r.missed << " of " << r.visible
          << " visible objects in frame " << f << " (eye " << pose.position.x << ", "
          << pose.position.y << ", " << pose.position.z << "; look at " << pose.look_at.x << ", "
          << pose.look_at.y << ", " << pose.look_at.z << "; render origin " << cam.render_origin.x
          << ", " << cam.render_origin.y << ", " << cam.render_origin.z << ")\n  first missed:";
      for (ObjectId id : r.missed_ids) {
        const Aabb& b = runner.objectBoxes()[id];
        out << "\n    object " << id << " box (" << b.min.x << ", " << b.min.y << ", " << b.min.z
            << ")-(" << b.max.x << ", " << b.max.y << ", " << b.max.z << ")";
      }
      out << "\n  reproduce: " << reproducer(key, config);
      return out.str();
    }();
    // Objects the oracle sets apart as depth-extrapolation artifacts
    // (logrid/gl/object_id_oracle.hpp) must also be drawn here: the small test walks have
    // none, so one that is not drawn is either a new artifact to look at or a culling bug
    // the classification hid.
    EXPECT_EQ(r.missed_artifacts, 0)
        << config.method.name() << " frame " << f << ": " << r.missed_artifacts
        << " objects shown only by fragments far nearer than their boxes were not drawn; "
           "reproduce: "
        << reproducer(key, config);
    EXPECT_TRUE(finiteStats(r)) << "frame " << f << ": ms " << r.ms << ", seconds "
                                << r.stats.seconds << ", read_seconds " << r.stats.read_seconds;
    t.visible += std::uint64_t(std::max<std::int64_t>(r.visible, 0));
    t.missed += std::uint64_t(std::max<std::int64_t>(r.missed, 0));
    t.artifacts += std::uint64_t(std::max<std::int64_t>(r.artifacts, 0));
    t.drawn += r.stats.objects_drawn;
    t.occluded += r.stats.boxes_occluded;
    t.tested += r.stats.boxes_tested;
    t.invalid += r.stats.invalid_boxes;
    t.occluders += std::uint64_t(std::max<std::int64_t>(r.occluders, 0));
    t.occluder_tiles += r.stats.occluder_tiles;
    t.backfacing += r.backfacing;
    if (r.cpu) t.cpu_moved += r.cpu->moved;
    t.ms += r.ms;
  }
  return t;
}

inline std::string summary(const WalkTotals& t) {
  char line[256];
  std::snprintf(line, sizeof line,
                "%zu frames: %llu visible, %llu missed, %llu artifacts, %llu drawn, %llu/%llu "
                "tests occluded, %.1f ms/frame",
                t.frames, (unsigned long long)t.visible, (unsigned long long)t.missed,
                (unsigned long long)t.artifacts, (unsigned long long)t.drawn,
                (unsigned long long)t.occluded, (unsigned long long)t.tested,
                t.frames ? t.ms / double(t.frames) : 0.0);
  return line;
}

// gtest parameter names allow only [A-Za-z0-9_].
inline std::string sanitize(std::string s) {
  for (char& ch : s) {
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  }
  return s;
}

// One oracle case: a walk over a scene with one method and its settings, every frame
// checked against the ID pass. What it must show besides zero misses (not vacuous):
// visible objects, boxes found occluded, DDO occluders selected, tiles recorded from them.
struct OracleCase {
  SceneKey scene;
  samples::MethodChoice method{Method::LogState};  // with its settings (:K, :tc, schedule)
  std::string reader = "readpixels";
  View view;
  std::size_t frames = 4;  // times LOGRID_ORACLE_INTENSITY
  std::string hierarchy;   // RunConfig::hierarchy; empty: auto
  double time_step = 0;    // RunConfig::time_step
  bool colliding = false;  // CullerDesc::detect_colliding
  bool expect_occluded = true;
  bool expect_occluders = false;
  bool expect_occluder_tiles = false;  // ddo+log: tiles recorded full from occluders
  bool expect_backfacing = false;      // clusters skipped for facing away (RunConfig)
  // Anything else of the run (the cpu reader's settings, the motion hierarchies', ...).
  std::function<void(RunConfig&)> adjust;
  std::string name;  // the gtest parameter name (sanitize()d) and the printed label
};

inline void PrintTo(const OracleCase& c, std::ostream* out) { *out << c.name; }
inline std::string oracleCaseName(const testing::TestParamInfo<OracleCase>& p) {
  return sanitize(p.param.name);
}

// The RunConfig of a case (the method's settings carried into CullerDesc, as the CLI does).
inline RunConfig configFor(const OracleCase& c, const PreparedScene& scene) {
  RunConfig config = makeConfig(scene, Method::LogState, c.reader, c.view, c.frames);
  config.method = c.method;
  if (c.method.lookahead) config.culler.lookahead = *c.method.lookahead;
  config.culler.temporal_coherence = c.method.coherence;
  if (c.method.schedule) config.culler.queries.schedule = *c.method.schedule;
  config.culler.detect_colliding = c.colliding;
  if (!c.hierarchy.empty()) config.hierarchy = c.hierarchy;
  config.time_step = c.time_step;
  if (c.adjust) c.adjust(config);
  return config;
}

// Walks the case over `scene` (loadScene(c.scene) in the overload below) and asserts zero
// misses and what the case expects; returns the totals for further checks.
inline WalkTotals checkCase(const OracleCase& c, LoadedScene& scene) {
  const RunConfig config = configFor(c, scene.prepared);
  const WalkTotals t = checkedWalk(c.scene, scene, config);
  std::printf("[ oracle ] %s: %s, %llu occluders, %llu tiles recorded from them\n",
              (c.name.empty() ? c.scene.name + " " + config.method.name() : c.name).c_str(),
              summary(t).c_str(), (unsigned long long)t.occluders,
              (unsigned long long)t.occluder_tiles);
  EXPECT_EQ(t.missed, 0u) << reproducer(c.scene, config);
  EXPECT_GT(t.visible, 0u) << "no object was visible; " << reproducer(c.scene, config);
  if (c.expect_occluded) {
    EXPECT_GT(t.occluded, 0u) << "no box was ever found occluded; the walk tests nothing; "
                              << reproducer(c.scene, config);
  }
  if (c.expect_occluders) {
    EXPECT_GT(t.occluders, 0u) << "no occluder was ever selected; " << reproducer(c.scene, config);
  }
  if (c.expect_backfacing) {
    EXPECT_GT(t.backfacing, 0u) << "no cluster was ever skipped for facing away; "
                                << reproducer(c.scene, config);
  }
  if (c.expect_occluder_tiles) {
    EXPECT_GT(t.occluder_tiles, 0u)
        << "no tile was recorded from the occluders' coverage; " << reproducer(c.scene, config);
  }
  return t;
}

inline WalkTotals checkCase(const OracleCase& c) { return checkCase(c, loadScene(c.scene)); }

// A method choice with its settings.
inline samples::MethodChoice choice(Method m, std::optional<std::uint32_t> lookahead = {},
                                    bool coherence = false) {
  samples::MethodChoice out{m};
  out.lookahead = lookahead;
  out.coherence = coherence;
  return out;
}

}  // namespace logrid::oracle
