#include "cli/options.hpp"

#include <cmath>

#include "cli/option_checks.hpp"
#include "cli/readers.hpp"
#include "cli/values.hpp"
#include "logrid/bvh/bvh.hpp"
#include "logrid/bvh/motion.hpp"
#include "logrid/camera.hpp"
#include "scene/generators.hpp"
#include "scene/movers.hpp"

namespace logrid::samples {
namespace {

constexpr std::uint32_t kMaxCount = std::numeric_limits<std::uint32_t>::max();
// Worker threads: the CPU occlusion buffer takes at most 64 (validateOcclusionBufferDesc),
// the DDO preprocessing 1024 (ddo::validateBuildArgs); llvmpipe at most 64 (LP_MAX_THREADS
// in Mesa 22) and multisampled framebuffers hold at most 64 samples on any driver we know.
constexpr std::uint32_t kMaxCpuThreads = 64;
constexpr std::uint32_t kMaxDdoThreads = 1024;
constexpr int kMaxLlvmpipeThreads = 64;
constexpr std::uint32_t kMaxSamples = 64;

}  // namespace

void addSceneOptions(CLI::App& app, WalkOptions& o) {
  app.add_option("--scene", o.scene, "forest, city, office, or a model file assimp reads")
      ->required();
  addWalkthroughOptions(app, o);
}

void addWalkthroughOptions(CLI::App& app, WalkOptions& o) {
  addNumber(app, "--scale", o.scale, above(0, kMaxForestScale),
            "scene size relative to the paper's (procedural scenes; the city up to " +
                std::to_string(int(kMaxCityScale)) + ", the office up to " +
                std::to_string(int(kMaxOfficeScale)) + ")");
  addNumber(app, "--seed", o.seed, NumberRange<std::uint64_t>{}, "seed of the procedural scenes");
  app.add_option("--path", o.path_file, "camera path JSON (keys: position, look_at, time)");
  addNumber(app, "--frames", o.frames, closed<std::size_t>(1, 10000000), "frames along the path");
  addNumber(app, "--time-step", o.time_step, closed(0.0, 1e9),
            "path time between frames from the path's start (seconds; metres on the "
            "procedural paths; default 0: the frames spread over the whole path)");
  addNumber(app, "--leaf", o.leaf, closed(0u, kMaxCount),
            "objects (or triangles) per hierarchy leaf; 0: the scene's");
  addNumber(app, "--cluster", o.cluster, closed(0u, 512u),
            "split every object into clusters of at most this many triangles (meshoptimizer; "
            "a multiple of 4, up to 512), each culled on its own box; 0: whole objects");
  app.add_option("--cluster-method", o.cluster_method,
                 "how --cluster groups an object's triangles: grow (compact clusters, the "
                 "default) or scan (a spatial sort cut in order: several times cheaper to "
                 "build, less compact; docs/CLUSTERS.md)");
  app.add_option("--tree-parts", o.tree_parts,
                 "forest: each tree one object (whole), trunk and crown apart (trunk-crown), or "
                 "the trunk and each crown tier apart (tiers)");
  addNumber(app, "--movers", o.movers, closed(0u, kMaxMovers),
            "add N moving objects (animals in the forest, vehicles in the city), "
            "deterministic from --seed");
  app.add_option("--animate", o.motion_file,
                 "a scene from a file: JSON paths its meshes move along (see docs/MOTION.md)");
  app.add_option("--platform", o.platform, "EGL platform: auto, surfaceless or device");
  addNumber(app, "--ddo-regions", o.ddo_regions, oneOf<std::uint32_t>({32, 64}),
            "DDO: view-direction regions per octree face");
  addNumber(app, "--ddo-leaf", o.ddo_leaf, closed(1u, kMaxCount),
            "DDO: triangles per octree leaf at most");
  app.add_option("--ddo-file", o.ddo_file,
                 "DDO: octree file to load or save (auto: FILE.ddo beside a model file, "
                 "FILE+ANIMATION.ddo with --animate; none)");
  app.add_flag("--ddo-rebuild", o.ddo_rebuild, "DDO: build again and overwrite the file");
  addNumber(app, "--ddo-threads", o.ddo_threads, closed(0u, kMaxDdoThreads),
            "DDO: preprocessing threads (0: all cores)");
  addLlvmpipeThreadsOption(app, o.lp_threads,
                           "llvmpipe raster threads (sets LP_NUM_THREADS; 0 makes each depth "
                           "read's flush ~10x cheaper but big frames slower)");
}

void addViewOptions(CLI::App& app, WalkOptions& o) {
  addNumber(app, "--tile", o.tile, closed(1u, kMaxViewportSide), "tile size in pixels");
  app.add_option("--reader", o.reader, "depth source: " + readerNames());
  app.add_option("--costs", o.costs,
                 "the cost model auto starts from: a file of `logrid calibrate --costs`, its "
                 "costs for --reader's source (default: built-in llvmpipe figures)");
  addLookaheadOption(app, o.lookahead,
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
  app.add_option("--cpu-buffer", o.cpu_buffer,
                 "--reader cpu: what the buffer holds: per-pixel (a key per pixel) or masked (a "
                 "coverage mask and two keys per 8x4 block)");
  app.add_option("--occluders", o.occluders,
                 "--reader cpu: what it rasterises per drawn object: mesh (its triangles) or "
                 "model (the scene's simpler occluder where it has one)");
  addNumber(app, "--occluder-pixels", o.occluder_pixels, closed(0.0, 1e9),
            "--reader cpu: rasterise only objects whose box covers at least this many pixels "
            "per occluder triangle (0: every drawn object)");
  addNumber(app, "--occluder-budget", o.occluder_budget, closed(0u, 4000000000u),
            "--reader cpu: occluder triangles rasterised per frame at most, in the order drawn "
            "(0: no budget)");
  addNumber(app, "--cpu-threads", o.cpu_threads, closed(0u, kMaxCpuThreads),
            "--reader cpu: threads that set up and rasterise, the caller among them (0: "
            "lazily in the caller; 1: binned in the caller; N: the caller and N - 1 workers)");
  app.add_option("--cpu-isa", o.cpu_isa, "--reader cpu: kernel auto, scalar, sse4.1 or avx2");
  app.add_option("--depth-format", o.depth_format, "depth buffer: 16, 24 or 32f");
  app.add_option("--depth-convention", o.depth_convention, "standard or reversed");
  addNumber(app, "--samples", o.samples, closed(0u, kMaxSamples),
            "samples per pixel (multisampled framebuffer; 0: single-sampled)");
  app.add_flag("--cull-back-faces", o.cull_back_faces,
               "the renderer culls back faces (counter-clockwise is front), frames and ID pass");
  app.add_flag("--backface-clusters", o.backface_clusters,
               "with --cluster and --cull-back-faces: clusters whose every triangle faces away "
               "are not drawn");
  addNumber(app, "--near", o.near_plane, NumberRange<double>{0, INFINITY, false, true, {}},
            "near plane (default 0: the scene's)");
  addNumber(app, "--far", o.far_plane, closed(0.0, double(INFINITY)),
            "far plane (default 0: the scene's; inf with --depth-convention reversed)");
  auto* fov = addNumber(app, "--fov", o.fov, NumberRange<double>{0, 180, true, true, {}},
                        "vertical field of view in degrees");
  app.add_flag("--ortho", o.ortho, "orthographic projection")->excludes(fov);
  addNumber(app, "--visible-pixels", o.approximation.visible_pixels, closed(0u, kMaxCount),
            "approximate: cull boxes showing at most N pixels (default 0: exact)");
  addNumber(app, "--full-fraction", o.approximation.full_free_fraction,
            NumberRange<float>{0, 1, false, true, {}},
            "approximate: tiles with at most this fraction free count as full (log-state, bog)");
  addNumber(app, "--row-stride", o.approximation.row_stride, closed(1u, kMaxViewportSide),
            "approximate: read every k-th pixel row of a tile, k up to the tile size (default "
            "1: every row)");
  addNumber(app, "--budget-ms", o.budget_ms, closed(0.0, 1e6),
            "frame-time budget in ms, the whole frame from clear to finish: the culler sets "
            "the approximate knobs itself to meet it (the full-tile fraction, then visible "
            "pixels; visible pixels alone with --coherence), exact when there is time "
            "(log-state, log-zfar, bog, ddo+log; default 0: none)");
  app.add_option("--query-schedule", o.query_schedule,
                 "log+hwq: schedule of the boxes the grid leaves undecided: " + querySchedules());
  app.add_option("--query-shape", o.query_shape,
                 "query methods: what a query draws: box (its faces) or rect (its rectangle)");
  app.add_flag("--any-samples", o.any_samples,
               "query methods: GL_ANY_SAMPLES_PASSED_CONSERVATIVE instead of GL_SAMPLES_PASSED");
  addNumber(app, "--chc-batch", o.chc_batch, closed(1u, kMaxCount),
            "chc: previously invisible nodes gathered before their multi-queries");
  addNumber(app, "--chc-interval", o.chc_interval, closed(1u, kMaxCount),
            "chc: frames a visible leaf goes without a query (n_av)");
  addNumber(app, "--stat-in-flight", o.stat_in_flight, closed(1u, kMaxCount),
            "stat: queries issued before the second pass collects them");
  addNumber(app, "--stat-base", o.stat_base, closed(1u, kMaxCount),
            "stat: BASE_TIME in frames (the paper's 2/3 s at 30 frames per second: 20)");
}

CLI::Option* addLlvmpipeThreadsOption(CLI::App& app, int& threads, const std::string& help) {
  return addNumber(app, "--lp-threads", threads, closed(0, kMaxLlvmpipeThreads), help);
}

CLI::Option* addSizeOption(CLI::App& app, std::string& size, const std::string& help) {
  return app.add_option("--size", size, help + " " + sizeForm())->check(sizeCheck());
}

CLI::Option* addLookaheadOption(CLI::App& app, std::string& lookahead, const std::string& help) {
  return app.add_option("--lookahead", lookahead, help + "; " + lookaheadRange())
      ->check(lookaheadCheck());
}

}  // namespace logrid::samples
