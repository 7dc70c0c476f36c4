#include "cli/common.hpp"

#include "cli/readers.hpp"
#include "cli/values.hpp"
#include "logrid/error.hpp"

namespace logrid::samples {

bool needsDdo(const std::string& method) {
  const auto choice = parseMethodChoice(method);
  return choice && choice->method && methodInfo(*choice->method).needs.occluders;
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
  if (!cpu::parseRepresentation(o.cpu_buffer, c.cpu.representation)) {
    throw Error(ErrorCode::InvalidArgument,
                "CPU buffer '" + o.cpu_buffer + "' is unknown; use per-pixel or masked");
  }
  const auto occluders = parseOccluderChoice(o.occluders);
  if (!occluders) {
    throw Error(ErrorCode::InvalidArgument,
                "occluders '" + o.occluders + "' is unknown; use mesh or model");
  }
  c.cpu.occluders = *occluders;
  c.cpu.threads = o.cpu_threads;
  c.cpu.min_pixels_per_triangle = o.occluder_pixels;
  c.cpu.triangle_budget = o.occluder_budget;
  if (!cpu::parseIsa(o.cpu_isa, c.cpu.isa)) {
    throw Error(ErrorCode::InvalidArgument,
                "CPU kernel '" + o.cpu_isa + "' is unknown; use auto, scalar, sse4.1 or avx2");
  }
  if (!cpu::isaSupported(c.cpu.isa)) {
    throw Error(ErrorCode::InvalidArgument,
                "this CPU does not run the " + o.cpu_isa + " kernel; use --cpu-isa auto or scalar");
  }
  c.culler.tile_size = o.tile;
  if (!o.costs.empty()) c.culler.costs = loadCullerCosts(o.costs, o.reader);
  c.culler.approximation = o.approximation;
  c.culler.budget_ms = o.budget_ms;
  // The runner times whole frames (clear to finish) and reports them: the budget controls
  // what the benchmark counts and a user sees.
  c.culler.budget_clock = BudgetClock::ReportedFrame;
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

}  // namespace logrid::samples
