#include "cli/common.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

#include "cli/readers.hpp"
#include "cli/report.hpp"
#include "logrid/error.hpp"
#include "scene/generators.hpp"
#include "scene/loader.hpp"
#include "scene/movers.hpp"

namespace logrid::samples {

void addSceneOptions(CLI::App& app, WalkOptions& o) {
  app.add_option("--scene", o.scene, "forest, city, office, or a model file assimp reads")
      ->required();
  addWalkthroughOptions(app, o);
}

void addWalkthroughOptions(CLI::App& app, WalkOptions& o) {
  app.add_option("--scale", o.scale, "scene size relative to the paper's (procedural scenes)");
  app.add_option("--seed", o.seed, "seed of the procedural scenes");
  app.add_option("--path", o.path_file, "camera path JSON (keys: position, look_at, time)");
  app.add_option("--frames", o.frames, "frames along the path")->check(CLI::Range(1, 10000000));
  app.add_option("--time-step", o.time_step,
                 "path time between frames from the path's start (seconds; metres on the "
                 "procedural paths; default 0: the frames spread over the whole path)")
      ->check(CLI::Range(0.0, 1e9));
  app.add_option("--leaf", o.leaf, "objects (or triangles) per hierarchy leaf; 0: the scene's");
  app.add_option("--tree-parts", o.tree_parts,
                 "forest: each tree one object (whole), trunk and crown apart (trunk-crown), or "
                 "the trunk and each crown tier apart (tiers)");
  app.add_option("--movers", o.movers,
                 "add N moving objects (animals in the forest, vehicles in the city), "
                 "deterministic from --seed")
      ->check(CLI::Range(0u, kMaxMovers));
  app.add_option("--animate", o.motion_file,
                 "a scene from a file: JSON paths its meshes move along (see docs/MOTION.md)");
  app.add_option("--platform", o.platform, "EGL platform: auto, surfaceless or device");
  app.add_option("--ddo-regions", o.ddo_regions,
                 "DDO: view-direction regions per octree face, 32 or 64");
  app.add_option("--ddo-leaf", o.ddo_leaf, "DDO: triangles per octree leaf at most");
  app.add_option("--ddo-file", o.ddo_file,
                 "DDO: octree file to load or save (auto: FILE.ddo beside a model file, "
                 "FILE+ANIMATION.ddo with --animate; none)");
  app.add_flag("--ddo-rebuild", o.ddo_rebuild, "DDO: build again and overwrite the file");
  app.add_option("--ddo-threads", o.ddo_threads, "DDO: preprocessing threads (0: all cores)");
  app.add_option("--lp-threads", o.lp_threads,
                 "llvmpipe raster threads (sets LP_NUM_THREADS; 0 makes each depth read's flush "
                 "~10x cheaper but big frames slower)")
      ->check(CLI::Range(0, 64));
}

void addViewOptions(CLI::App& app, WalkOptions& o) {
  app.add_option("--tile", o.tile, "tile size in pixels");
  app.add_option("--reader", o.reader, "depth source: " + readerNames());
  app.add_option("--lookahead", o.lookahead,
                 "boxes whose undecided tiles are read in one batch (1: the paper's order; "
                 "'all': every box the traversal reaches)");
  app.add_flag("--coherence,!--no-coherence", o.coherence,
               "draw last frame's visible leaves first, then refresh the grid in one batch");
  app.add_option(
      "--hierarchy", o.hierarchy,
      "hierarchy culled: auto (static without movers, refit with), static, " + bvh::motionNames());
  app.add_flag("--colliding", o.colliding,
               "with --lookahead > 1: keep boxes that overlap on screen out of one batch "
               "(colliding-query detection)");
  app.add_option("--cpu-resolution", o.cpu_resolution,
                 "--reader cpu: buffer resolution full, half or quarter");
  app.add_option("--occluders", o.occluders,
                 "--reader cpu: what it rasterises per drawn object: mesh (its triangles) or "
                 "model (the scene's simpler occluder where it has one)");
  app.add_option("--cpu-threads", o.cpu_threads, "--reader cpu: worker threads (0: none)")
      ->check(CLI::Range(0, 64));
  app.add_option("--cpu-isa", o.cpu_isa, "--reader cpu: kernel auto, scalar, sse4.1 or avx2");
  app.add_option("--depth-format", o.depth_format, "depth buffer: 16, 24 or 32f");
  app.add_option("--depth-convention", o.depth_convention, "standard or reversed");
  app.add_option("--samples", o.samples,
                 "samples per pixel (multisampled framebuffer; 0: single-sampled)")
      ->check(CLI::Range(0, 64));
  app.add_option("--near", o.near_plane, "near plane (default: the scene's)");
  app.add_option("--far", o.far_plane, "far plane (default: the scene's)");
  auto* fov = app.add_option("--fov", o.fov, "vertical field of view in degrees");
  app.add_flag("--ortho", o.ortho, "orthographic projection")->excludes(fov);
  app.add_option("--visible-pixels", o.approximation.visible_pixels,
                 "approximate: cull boxes showing at most N pixels (default 0: exact)");
  app.add_option(
      "--full-fraction", o.approximation.full_free_fraction,
      "approximate: tiles with at most this fraction free count as full (log-state, bog)");
  app.add_option("--row-stride", o.approximation.row_stride,
                 "approximate: read every k-th pixel row of a tile (default 1: every row)");
  app.add_option("--query-schedule", o.query_schedule,
                 "log+hwq: schedule of the boxes the grid leaves undecided: " + querySchedules());
  app.add_option("--query-shape", o.query_shape,
                 "query methods: what a query draws: box (its faces) or rect (its rectangle)");
  app.add_flag("--any-samples", o.any_samples,
               "query methods: GL_ANY_SAMPLES_PASSED_CONSERVATIVE instead of GL_SAMPLES_PASSED");
  app.add_option("--chc-batch", o.chc_batch,
                 "chc: previously invisible nodes gathered before their multi-queries");
  app.add_option("--chc-interval", o.chc_interval,
                 "chc: frames a visible leaf goes without a query (n_av)");
  app.add_option("--stat-in-flight", o.stat_in_flight,
                 "stat: queries issued before the second pass collects them");
  app.add_option("--stat-base", o.stat_base,
                 "stat: BASE_TIME in frames (the paper's 2/3 s at 30 frames per second: 20)");
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

std::pair<std::uint32_t, std::uint32_t> parseSize(const std::string& text) {
  unsigned long w = 0, h = 0;
  char x = 0, extra = 0;
  std::istringstream in(text);
  if (!(in >> w >> x >> h) || (x != 'x' && x != 'X') || (in >> extra) || w < 1 || h < 1 ||
      w > kMaxViewportSide || h > kMaxViewportSide) {
    throw Error(ErrorCode::InvalidArgument,
                "size '" + text + "' is invalid; use WIDTHxHEIGHT with each side from 1 to " +
                    std::to_string(kMaxViewportSide) + ", e.g. 640x480");
  }
  return {std::uint32_t(w), std::uint32_t(h)};
}

DepthFormat parseDepthFormat(const std::string& text) {
  if (text == "16") return DepthFormat::D16;
  if (text == "24") return DepthFormat::D24;
  if (text == "32f" || text == "32F") return DepthFormat::D32F;
  throw Error(ErrorCode::InvalidArgument,
              "depth format '" + text + "' is unknown; use 16, 24 or 32f");
}

DepthConvention parseDepthConvention(const std::string& text) {
  if (text == "standard") return DepthConvention::Standard;
  if (text == "reversed") return DepthConvention::Reversed;
  throw Error(ErrorCode::InvalidArgument,
              "depth convention '" + text + "' is unknown; use standard or reversed");
}

TreeParts parseTreeParts(const std::string& text) {
  for (TreeParts p : {TreeParts::Whole, TreeParts::TrunkCrown, TreeParts::Tiers}) {
    if (text == toString(p)) return p;
  }
  throw Error(ErrorCode::InvalidArgument,
              "tree parts '" + text + "' is unknown; use whole, trunk-crown or tiers");
}

std::uint32_t parseLookahead(const std::string& text) {
  if (text == "all") return kUnlimitedLookahead;
  unsigned long k = 0;
  char extra = 0;
  std::istringstream in(text);
  if (!(in >> k) || (in >> extra) || k < 1 || k >= kUnlimitedLookahead) {
    throw Error(ErrorCode::InvalidArgument,
                "lookahead '" + text + "' is invalid; use a number of boxes from 1 or 'all'");
  }
  return std::uint32_t(k);
}

namespace {

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

nlohmann::json LoadedScene::describe() const {
  const PreparedScene& p = prepared;
  return {{"scene", p.name},
          {"scene_triangles", p.triangles},
          {"scene_objects", p.mesh.draws.size()},
          {"source_objects", p.source_objects},
          {"hierarchy_nodes", p.hierarchy.nodes().size()},
          {"hierarchy_depth", p.hierarchy.depth()},
          {"generate_ms", generate_ms},
          {"bvh_build_ms", p.bvh_build_ms},
          {"prepare_ms", p.prepare_ms},
          {"cpu_bytes", p.memoryBytes()},
          {"gpu_bytes", renderer ? renderer->gpuBytes() : 0},
          {"peak_rss_bytes", peak_rss_bytes},
          {"prepare_peak_rss_bytes", prepare_peak_rss_bytes},
          {"bytes_per_triangle", p.triangles ? double(peak_rss_bytes) / double(p.triangles) : 0.0},
          {"ddo", ddo ? describeDdo(*ddo) : nlohmann::json()}};
}

WalkOptions optionsForScene(const WalkOptions& base, const std::string& scene, double forest_scale,
                            double city_scale) {
  WalkOptions o = base;
  o.scene = scene;
  if (scene == "forest" && forest_scale > 0) o.scale = forest_scale;
  if (scene == "city" && city_scale > 0) o.scale = city_scale;
  return o;
}

bool needsDdo(const std::string& method) {
  const auto choice = parseMethodChoice(method);
  return choice && choice->method && methodInfo(*choice->method).needs.occluders;
}

DdoOptions ddoOptions(const WalkOptions& o) {
  DdoOptions d;
  d.regions = o.ddo_regions;
  d.leaf_triangles = o.ddo_leaf;
  d.threads = o.ddo_threads;
  d.rebuild = o.ddo_rebuild;
  d.file = o.ddo_file == "auto"   ? defaultDdoFile(o.scene, o.motion_file)
           : o.ddo_file == "none" ? ""
                                  : o.ddo_file;
  return d;
}

nlohmann::json describeDdo(const DdoScene& d) {
  const ddo::Octree& o = *d.octree;
  const ddo::BuildReport& r = d.report;
  const double nodes = double(o.nodes().size());
  std::uint64_t valid_faces = 0;
  for (std::uint64_t m : o.masks()) valid_faces += m != 0;
  return {{"file", d.file},
          {"loaded", d.loaded},
          {"regions", o.params().regions},
          {"leaf_triangles", o.params().leaf_triangles},
          {"nodes", o.nodes().size()},
          {"depth", o.depth()},
          {"faces", o.nodes().size() * ddo::kFaces},
          {"valid_faces", valid_faces},
          {"mask_bytes", o.maskBytes()},
          {"mask_bytes_per_node", nodes > 0 ? double(o.maskBytes()) / nodes : 0.0},
          {"file_mask_bytes_per_face", o.params().regions / 8},
          {"octree_bytes", o.memoryBytes()},
          {"octree_bytes_per_node", nodes > 0 ? double(o.memoryBytes()) / nodes : 0.0},
          {"file_bytes", d.file_bytes},
          {"checksum_ms", d.checksum_ms},
          {"load_ms", d.load_ms},
          {"save_ms", d.save_ms},
          {"build",
           {{"threads", r.threads},
            {"octree_ms", r.octree_ms},
            {"topology_ms", r.topology_ms},
            {"index_ms", r.index_ms},
            {"faces_ms", r.faces_ms},
            {"total_ms", r.total_ms},
            {"leaves", r.leaves},
            {"faces_nothing_behind", r.faces_nothing_behind},
            {"faces_valid", r.faces_valid},
            {"regions_tested", r.regions_tested},
            {"regions_valid", r.regions_valid},
            {"regions_degenerate", r.regions_degenerate},
            {"pieces_followed", r.pieces_followed},
            {"pieces_abandoned", r.pieces_abandoned},
            {"pieces_open", r.pieces_open},
            {"corner_misses", r.corner_misses},
            {"pieces_closed_even", r.pieces_closed_even},
            {"piece_triangles", r.piece_triangles},
            {"temporary_bytes", r.temporary_bytes}}}};
}

LoadedScene loadScene(const WalkOptions& o, bool upload, bool with_ddo) {
  LoadedScene out;
  const auto start = std::chrono::steady_clock::now();
  Scene scene;
  if (o.scene == "forest") {
    scene = makeForest({o.scale, o.seed, parseTreeParts(o.tree_parts)});
  } else if (o.scene == "city") {
    scene = makeCity({o.scale, o.seed});
  } else if (o.scene == "office") {
    scene = makeOffice({o.scale, o.seed});
  } else {
    scene = loadSceneFile(o.scene);
  }
  if (!o.path_file.empty()) scene.path = CameraPath::fromJsonFile(o.path_file);
  if (!o.motion_file.empty()) animateMeshes(scene, o.motion_file);
  addMovers(scene, o.movers, o.seed);
  out.generate_ms = msSince(start);
  bvh::BuildArgs args = defaultBuildArgs(scene);
  if (o.leaf) args.max_leaf_size = o.leaf;
  out.prepared = prepareScene(std::move(scene), args);
  out.prepare_peak_rss_bytes = peakRssBytes();
  if (with_ddo) {
    out.ddo = prepareDdo(out.prepared, ddoOptions(o));
    out.prepared.ddo = out.ddo->octree;
  }
  if (upload) out.renderer = std::make_unique<gl::MeshRenderer>(out.prepared.mesh);
  out.peak_rss_bytes = peakRssBytes();
  return out;
}

RunConfig runConfig(const WalkOptions& o, const PreparedScene& scene) {
  RunConfig c;
  std::string problem;
  const auto method = parseMethodChoice(o.method, &problem);
  if (!method) throw Error(ErrorCode::InvalidArgument, problem);
  c.method = *method;
  if (!findReader(o.reader)) {
    throw Error(ErrorCode::InvalidArgument,
                "reader '" + o.reader + "' is unknown; use " + readerNames());
  }
  c.reader = o.reader;
  if (!cpu::parseResolution(o.cpu_resolution, c.cpu.resolution)) {
    throw Error(ErrorCode::InvalidArgument, "CPU buffer resolution '" + o.cpu_resolution +
                                                "' is unknown; use full, half or quarter");
  }
  const auto occluders = parseOccluderChoice(o.occluders);
  if (!occluders) {
    throw Error(ErrorCode::InvalidArgument,
                "occluders '" + o.occluders + "' is unknown; use mesh or model");
  }
  c.cpu.occluders = *occluders;
  c.cpu.threads = o.cpu_threads;
  if (!cpu::parseIsa(o.cpu_isa, c.cpu.isa)) {
    throw Error(ErrorCode::InvalidArgument,
                "CPU kernel '" + o.cpu_isa + "' is unknown; use auto, scalar, sse4.1 or avx2");
  }
  if (!cpu::isaSupported(c.cpu.isa)) {
    throw Error(ErrorCode::InvalidArgument,
                "this CPU does not run the " + o.cpu_isa + " kernel; use --cpu-isa auto or scalar");
  }
  c.culler.tile_size = o.tile;
  if (o.tile < 1)
    throw Error(ErrorCode::InvalidArgument, "tile size 0 is invalid; use 1 pixel or more");
  c.culler.approximation = o.approximation;
  c.culler.lookahead = c.method.lookahead ? *c.method.lookahead : parseLookahead(o.lookahead);
  c.culler.temporal_coherence = c.method.coherence || o.coherence;
  c.culler.detect_colliding = o.colliding;
  if (o.hierarchy != "auto" && o.hierarchy != "static" && !bvh::parseMotionKind(o.hierarchy)) {
    throw Error(
        ErrorCode::InvalidArgument,
        "hierarchy '" + o.hierarchy + "' is unknown; use auto, static, " + bvh::motionNames());
  }
  if (o.hierarchy == "static" && !scene.motion.empty()) {
    throw Error(ErrorCode::InvalidArgument, "--hierarchy static holds none of the scene's " +
                                                std::to_string(scene.motion.movers.size()) +
                                                " moving objects; use " + bvh::motionNames());
  }
  c.hierarchy = o.hierarchy;
  c.time_step = o.time_step;
  QueryScheduleDesc& q = c.culler.queries;
  const auto schedule = parseQuerySchedule(o.query_schedule);
  if (!schedule) {
    throw Error(ErrorCode::InvalidArgument,
                "query schedule '" + o.query_schedule + "' is unknown; use " + querySchedules());
  }
  q.schedule = c.method.schedule ? *c.method.schedule : *schedule;
  if (o.query_shape != "box" && o.query_shape != "rect") {
    throw Error(ErrorCode::InvalidArgument,
                "query shape '" + o.query_shape + "' is unknown; use box or rect");
  }
  q.shape = o.query_shape == "rect" ? QueryShape::Rect : QueryShape::Box;
  q.chc_batch = o.chc_batch;
  q.chc_visible_interval = o.chc_interval;
  q.stat_in_flight = o.stat_in_flight;
  q.stat_base_frames = o.stat_base;
  c.any_samples_passed = o.any_samples;
  if (c.method.method) {
    CullerDesc check = c.culler;
    check.method = *c.method.method;
    measureHardwareIfNeeded(check);  // nohc: measured on this context's renderer
    c.culler.queries.hardware = check.queries.hardware;
    problem = validateCullerDesc(check);
    if (!problem.empty()) throw Error(ErrorCode::InvalidArgument, problem);
  }
  const auto [w, h] = parseSize(o.size);
  c.view.width = w;
  c.view.height = h;
  c.view.fov_degrees = o.fov;
  if (!(o.fov > 0 && o.fov < 180)) {
    throw Error(ErrorCode::InvalidArgument, "field of view " + std::to_string(o.fov) +
                                                " is invalid; use 0 < fov < 180 degrees");
  }
  c.view.orthographic = o.ortho;
  c.view.near_plane = o.near_plane > 0 ? o.near_plane : scene.near_plane;
  c.view.far_plane = o.far_plane > 0 ? o.far_plane : scene.far_plane;
  if (!(c.view.far_plane > c.view.near_plane)) {
    throw Error(ErrorCode::InvalidArgument, "far plane " + std::to_string(c.view.far_plane) +
                                                " must lie beyond the near plane " +
                                                std::to_string(c.view.near_plane));
  }
  c.view.depth =
      depthSetupFor(parseDepthConvention(o.depth_convention), parseDepthFormat(o.depth_format));
  c.view.samples = o.samples;
  c.frames = o.frames;
  c.verify = o.verify;
  c.images_dir = o.images;
  c.overlay = o.overlay;
  return c;
}

gl::ContextDesc contextDesc(const WalkOptions& o) {
  gl::ContextDesc d;
  const auto platform = gl::parsePlatform(o.platform);
  if (!platform) {
    throw Error(ErrorCode::InvalidArgument,
                "platform '" + o.platform + "' is unknown; use auto, surfaceless or device");
  }
  d.platform = *platform;
  // Mesa reads LP_NUM_THREADS when the driver starts, i.e. when the context is made.
  if (o.lp_threads >= 0) setenv("LP_NUM_THREADS", std::to_string(o.lp_threads).c_str(), 1);
  return d;
}

namespace {
std::string g_command_line;
}

void setCommandLine(int argc, char** argv) {
  g_command_line.clear();
  for (int i = 0; i < argc; ++i) {
    if (i) g_command_line += ' ';
    const std::string arg = i == 0 ? "logrid" : argv[i];
    const bool quote = arg.find_first_of(" \t'\"") != std::string::npos;
    g_command_line += quote ? "'" + arg + "'" : arg;
  }
}

const std::string& commandLine() { return g_command_line; }

nlohmann::json machineInfo(const gl::Context& context) {
  std::string cpu;
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; std::getline(info, line);) {
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  }
  const char* lp = std::getenv("LP_NUM_THREADS");
  const gl::ContextInfo& gl = context.info();
  return {{"gl_renderer", gl.renderer},
          {"gl_version", gl.version},
          {"gl_vendor", gl.vendor},
          {"egl_platform", gl::toString(gl.platform)},
          {"software_rasterizer", gl.software},
          {"cores", std::thread::hardware_concurrency()},
          {"cpu", cpu},
          {"lp_num_threads", lp ? lp : ""}};
}

std::string machineLine(const nlohmann::json& m) {
  std::ostringstream out;
  out << m["gl_renderer"].get<std::string>() << " (" << m["gl_version"].get<std::string>() << "), "
      << m["cores"].get<unsigned>() << " cores, " << m["cpu"].get<std::string>();
  return out.str();
}

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)), total_(total), tty_(isatty(STDERR_FILENO) != 0) {}

void Progress::update(std::size_t done, double ms) {
  if (tty_) {
    std::fprintf(stderr, "\r%s: frame %zu/%zu, %.2f ms/frame   ", label_.c_str(), done, total_, ms);
    std::fflush(stderr);
    return;
  }
  const std::size_t percent = done * 100 / std::max<std::size_t>(total_, 1);
  if (done == total_ || percent >= last_percent_ + 10) {
    last_percent_ = percent;
    std::fprintf(stderr, "%s: frame %zu/%zu, %.2f ms/frame\n", label_.c_str(), done, total_, ms);
  }
}

void Progress::finish() {
  if (tty_) std::fprintf(stderr, "\n");
}

std::uint64_t peakRssBytes() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stoull(line.substr(6)) * 1024;
  }
  return 0;
}

void writeJson(const std::string& path, const nlohmann::json& json) {
  writeText(path, json.dump(2) + "\n");
}

}  // namespace logrid::samples
