#include "cli/common.hpp"

#include "cli/readers.hpp"
#include "cli/values.hpp"
#include "logrid/error.hpp"

namespace logrid::samples {

bool needsDdo(const std::string& method) {
  const auto choice = parseMethodChoice(method);
  return choice && choice->method && methodInfo(*choice->method).needs.occluders;
}

namespace {

// --reader cpu's settings.
CpuReaderOptions cpuReaderOptions(const WalkOptions& o) {
  CpuReaderOptions cpu;
  if (!cpu::parseResolution(o.cpu_resolution, cpu.resolution)) {
    throw Error(ErrorCode::InvalidArgument, "CPU buffer resolution '" + o.cpu_resolution +
                                                "' is unknown; use full, half or quarter");
  }
  if (!cpu::parseRepresentation(o.cpu_buffer, cpu.representation)) {
    throw Error(ErrorCode::InvalidArgument,
                "CPU buffer '" + o.cpu_buffer + "' is unknown; use per-pixel or masked");
  }
  const auto occluders = parseOccluderChoice(o.occluders);
  if (!occluders) {
    throw Error(ErrorCode::InvalidArgument,
                "occluders '" + o.occluders + "' is unknown; use mesh or model");
  }
  cpu.occluders = *occluders;
  cpu.threads = o.cpu_threads;
  cpu.min_pixels_per_triangle = o.occluder_pixels;
  cpu.triangle_budget = o.occluder_budget;
  if (!cpu::parseIsa(o.cpu_isa, cpu.isa)) {
    throw Error(ErrorCode::InvalidArgument,
                "CPU kernel '" + o.cpu_isa + "' is unknown; use auto, scalar, sse4.1 or avx2");
  }
  if (!cpu::isaSupported(cpu.isa)) {
    throw Error(ErrorCode::InvalidArgument,
                "this CPU does not run the " + o.cpu_isa + " kernel; use --cpu-isa auto or scalar");
  }
  return cpu;
}

void checkHierarchy(const WalkOptions& o, const PreparedScene& scene) {
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
}

// The query schedules' settings; a method that names its schedule runs that one.
QueryScheduleDesc querySettings(const WalkOptions& o, const MethodChoice& method) {
  QueryScheduleDesc q;
  const auto schedule = parseQuerySchedule(o.query_schedule);
  if (!schedule) {
    throw Error(ErrorCode::InvalidArgument,
                "query schedule '" + o.query_schedule + "' is unknown; use " + querySchedules());
  }
  q.schedule = method.schedule ? *method.schedule : *schedule;
  if (o.query_shape != "box" && o.query_shape != "rect") {
    throw Error(ErrorCode::InvalidArgument,
                "query shape '" + o.query_shape + "' is unknown; use box or rect");
  }
  q.shape = o.query_shape == "rect" ? QueryShape::Rect : QueryShape::Box;
  q.chc_batch = o.chc_batch;
  q.chc_visible_interval = o.chc_interval;
  q.stat_in_flight = o.stat_in_flight;
  q.stat_base_frames = o.stat_base;
  return q;
}

// The culler's settings but its query schedule's.
CullerDesc cullerSettings(const WalkOptions& o, const MethodChoice& method) {
  CullerDesc culler;
  culler.tile_size = o.tile;
  if (!o.costs.empty()) culler.costs = loadCullerCosts(o.costs, o.reader);
  culler.approximation = o.approximation;
  culler.budget_ms = o.budget_ms;
  // The runner times whole frames (clear to finish) and reports them: the cost estimate,
  // auto and the budget learn from what the benchmark counts and a user sees.
  culler.frame_clock = FrameClock::ReportedFrame;
  culler.lookahead = method.lookahead ? *method.lookahead : parseLookahead(o.lookahead);
  culler.temporal_coherence = method.coherence || o.coherence;
  culler.detect_colliding = o.colliding;
  return culler;
}

// The library's validator on the culler's settings where the method is known (nohc's
// hardware figures measured first, on this context's renderer).
void checkCuller(CullerDesc& culler, const MethodChoice& method) {
  if (!method.method) return;
  CullerDesc check = culler;
  check.method = *method.method;
  measureHardwareIfNeeded(check);
  culler.queries.hardware = check.queries.hardware;
  const std::string problem = validateCullerDesc(check);
  if (!problem.empty()) throw Error(ErrorCode::InvalidArgument, problem);
}

// The view: size, projection, planes (the scene's where not given), depth.
ViewSettings viewSettings(const WalkOptions& o, const PreparedScene& scene) {
  ViewSettings view;
  const auto [w, h] = parseSize(o.size);
  view.width = w;
  view.height = h;
  view.fov_degrees = o.fov;
  view.orthographic = o.ortho;
  view.near_plane = o.near_plane > 0 ? o.near_plane : scene.near_plane;
  view.far_plane = o.far_plane > 0 ? o.far_plane : scene.far_plane;
  if (!(view.far_plane > view.near_plane)) {
    throw Error(ErrorCode::InvalidArgument, "far plane " + std::to_string(view.far_plane) +
                                                " must lie beyond the near plane " +
                                                std::to_string(view.near_plane));
  }
  view.depth =
      depthSetupFor(parseDepthConvention(o.depth_convention), parseDepthFormat(o.depth_format));
  view.samples = o.samples;
  view.cull_back_faces = o.cull_back_faces;
  return view;
}

}  // namespace

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
  c.cpu = cpuReaderOptions(o);
  c.culler = cullerSettings(o, c.method);
  checkHierarchy(o, scene);
  c.hierarchy = o.hierarchy;
  c.time_step = o.time_step;
  c.culler.queries = querySettings(o, c.method);
  c.any_samples_passed = o.any_samples;
  checkCuller(c.culler, c.method);
  c.view = viewSettings(o, scene);
  c.backface_clusters = o.backface_clusters;
  c.frames = o.frames;
  c.verify = o.verify;
  c.images_dir = o.images;
  c.overlay = o.overlay;
  return c;
}

}  // namespace logrid::samples
