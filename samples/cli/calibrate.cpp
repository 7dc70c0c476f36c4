// logrid calibrate: the hardware parameters of Guthe et al.'s cost model (NOHC §3.2,
// Table 2) measured on this machine's renderer, as the nohc method measures them at
// start-up (zread/calibration.hpp), with what nohc derives from them (§4.3); and the
// costs of the `auto` method's model (logrid/costs.hpp) for each depth source that reads
// the framebuffer, written with --costs as the file the library loads.
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <random>
#include <vector>

#include "cli/commands.hpp"
#include "cli/machine.hpp"
#include "cli/option_checks.hpp"
#include "cli/options.hpp"
#include "cli/readers.hpp"
#include "cli/report.hpp"
#include "logrid/costs.hpp"
#include "logrid/elapsed.hpp"
#include "logrid/error.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/projection.hpp"
#include "logrid/zread/calibration.hpp"
#include "scene/view.hpp"

namespace logrid::samples {
namespace {

struct CalibrateOptions {
  WalkOptions walk;  // --platform, --lp-threads
  std::uint32_t size = 512;
  std::uint32_t repeats = 5;
  std::string json;
  std::string costs;  // --costs FILE
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// Seconds of one box through the traversal's CPU work: its projection (measured over
// random boxes in front of the camera), doubled for the test-list and the records.
double boxTestSeconds(const Camera& camera, std::uint32_t repeats) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> xy(-3, 3), z(-20, -2), s(0.1f, 1.0f);
  std::vector<Aabb> boxes(4096);
  for (Aabb& b : boxes) {
    const Vec3 lo{xy(rng), xy(rng), z(rng)};
    b = {lo, {lo.x + s(rng), lo.y + s(rng), lo.z + s(rng)}};
  }
  const Projector projector(camera);
  std::vector<double> runs;
  float sink = 0;
  for (std::uint32_t r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    for (const Aabb& b : boxes) sink += projector.project(b).near_key;
    runs.push_back(secondsSince(start) / double(boxes.size()));
  }
  if (sink == 12345.0f) std::printf(" ");  // keeps the loop
  return 2.0 * median(runs);
}

// A flush and a pixel of `reader`: the median time of a read of one pixel right after a
// one-pixel draw (the renderer must finish it first), and of a 64 x 64 read the same way;
// the difference is 4095 pixels.
struct SourceTimes {
  double flush_s = 0;
  double pixel_s = 0;
};

SourceTimes measureSource(const ReaderInfo& reader, const gl::Framebuffer& fb, const Camera& camera,
                          std::uint32_t repeats) {
  static const PreparedScene kNoScene{};
  const ReaderContext context{kNoScene,      fb.handle(),          camera.width,
                              camera.height, camera.depth,         nullptr,
                              nullptr,       ProjectionSettings{}, Method::LogZfar};
  std::unique_ptr<FrameReader> frame_reader = reader.make(context);
  DepthSource& source = frame_reader->source();
  const float clear[4] = {0, 0, 0, 1};
  fb.bind();
  fb.clear(clear);
  orThrow(source.beginFrame(camera));
  const std::int32_t c = std::int32_t(camera.width / 2);
  auto timedReads = [&](std::int32_t side) {
    AreaRequest request;
    request.rect = {c, c, c + side, c + side};
    request.ask = reader.reads_depth ? AreaAsk::Summary : AreaAsk::Count;
    request.threshold = 0.5f;
    AreaAnswer answer;
    std::vector<double> runs;
    for (std::uint32_t r = 0; r < repeats + 2; ++r) {
      glFinish();
      const auto start = std::chrono::steady_clock::now();
      constexpr int kReads = 20;
      for (int i = 0; i < kReads; ++i) {
        // A one-pixel draw the read must wait for: a scissored depth clear.
        glEnable(GL_SCISSOR_TEST);
        glScissor(0, 0, 1, 1);
        glClear(GL_DEPTH_BUFFER_BIT);
        glDisable(GL_SCISSOR_TEST);
        source.noteDraw();
        source.submit(&request, 1, &answer);
        source.collect();
      }
      if (r >= 2) runs.push_back(secondsSince(start) / kReads);  // two warm-up runs
    }
    return median(runs);
  };
  const double one = timedReads(1);
  const double tile = timedReads(64);
  orThrow(source.endFrame());
  orThrow(source.takeError());
  SourceTimes t;
  t.pixel_s = std::max(tile - one, 0.0) / (64.0 * 64.0 - 1.0);
  t.flush_s = std::max(one - t.pixel_s, 1e-9);
  t.pixel_s = std::max(t.pixel_s, 1e-12);
  return t;
}

// The cost model of `auto` for each source that reads the framebuffer.
CullerCostsFile measureCosts(const HardwareParameters& p, const std::string& machine,
                             std::uint32_t size, std::uint32_t repeats) {
  ViewSettings view;
  view.width = view.height = size;
  view.depth = depthSetupFor(DepthConvention::Standard, DepthFormat::D32F);
  CameraPose pose;
  pose.position = {0, 0, 0};
  pose.look_at = {0, 0, -1};
  const Camera camera = makeCamera(pose, glm::dvec3(0.0), view);
  gl::Framebuffer fb({size, size, view.depth});
  CullerCostsFile file;
  file.machine = machine;
  const double box_test = boxTestSeconds(camera, repeats);
  for (const ReaderInfo& reader : readerTable()) {
    if (!reader.reads_framebuffer) continue;
    const SourceTimes t = measureSource(reader, fb, camera, repeats);
    CullerCosts c;
    c.flush_s = t.flush_s;
    c.pixel_s = t.pixel_s;
    c.box_test_s = box_test;
    c.triangle_s = std::max(p.render_triangle, 1e-12);
    c.draw_s = std::max(p.render_setup, 1e-9);
    c.query_s = std::max(p.query_setup, 1e-9);
    file.sources[reader.name] = c;
  }
  return file;
}

std::string microseconds(double s) {
  return s >= 1e-6 ? formatFixed(s * 1e6, 3) + " µs" : formatFixed(s * 1e9, 3) + " ns";
}

int runCalibrate(const CalibrateOptions& o) {
  gl::Context context(contextDesc(o.walk));
  zread::CalibrationDesc desc;
  desc.size = o.size;
  desc.repeats = o.repeats;
  const HardwareParameters p = zread::measureHardwareParameters(desc);
  const double per_query = std::min(p.query_setup, p.query_overhead + p.render_setup);
  const double nq = per_query > 0 ? std::ceil(p.query_latency / per_query) + 1 : 1;
  const bool poll = p.poll <= p.query_setup;

  std::printf("Renderer: %s\n", machineLine(machineInfo(context)).c_str());
  std::printf("Measured in a %ux%u framebuffer, median of %u runs (NOHC §3.2.2, Table 2):\n",
              o.size, o.size, o.repeats);
  const struct {
    const char* symbol;
    const char* what;
    double value;
  } rows[] = {{"T_r^s", "setup time per rendering call", p.render_setup},
              {"T_r^tri", "time per rendered triangle", p.render_triangle},
              {"T_r^f", "time per shaded fragment", p.render_fragment},
              {"T_o^s", "setup time per occlusion query", p.query_setup},
              {"T_o^f", "time per fragment during an occlusion query", p.query_fragment},
              {"T_o^l", "maximum occlusion query latency", p.query_latency},
              {"T_o^o", "overhead of a query issued along with rendering", p.query_overhead},
              {"poll", "an availability poll right after a draw (§4.3)", p.poll}};
  for (const auto& r : rows) {
    std::printf("  %-8s %-50s %14s\n", r.symbol, r.what, microseconds(r.value).c_str());
  }
  std::printf(
      "Derived (§4.3): N_q = ceil(T_o^l / min(T_o^s, T_o^o + T_r^s)) + 1 = %.0f queries "
      "in flight; availability polls %s (a poll %s a query's setup).\n",
      std::min(nq, 1024.0), poll ? "used" : "not used",
      poll ? "costs no more than" : "costs more than");
  const CullerCostsFile costs =
      measureCosts(p, machineLine(machineInfo(context)), o.size, o.repeats);
  std::printf("The auto method's cost model (logrid/costs.hpp), per depth source:\n");
  std::printf("  %-11s %12s %12s %12s %12s %12s %12s\n", "source", "flush", "pixel", "box test",
              "triangle", "draw", "query");
  nlohmann::json costs_json = nlohmann::json::object();
  for (const auto& [name, c] : costs.sources) {
    std::printf("  %-11s %12s %12s %12s %12s %12s %12s\n", name.c_str(),
                microseconds(c.flush_s).c_str(), microseconds(c.pixel_s).c_str(),
                microseconds(c.box_test_s).c_str(), microseconds(c.triangle_s).c_str(),
                microseconds(c.draw_s).c_str(), microseconds(c.query_s).c_str());
    costs_json[name] = {{"flush_s", c.flush_s},       {"pixel_s", c.pixel_s},
                        {"box_test_s", c.box_test_s}, {"triangle_s", c.triangle_s},
                        {"draw_s", c.draw_s},         {"query_s", c.query_s}};
  }
  if (!o.costs.empty()) {
    std::ofstream out(o.costs, std::ios::binary);
    out << formatCullerCosts(costs);
    if (!out) {
      throw Error(ErrorCode::Environment, "cannot write the costs file " + o.costs);
    }
    std::printf("Wrote %s (walk, bench and view take it with --costs).\n", o.costs.c_str());
  }
  if (!o.json.empty()) {
    writeJson(o.json, {{"machine", machineInfo(context)},
                       {"costs", costs_json},
                       {"size", o.size},
                       {"repeats", o.repeats},
                       {"render_setup_s", p.render_setup},
                       {"render_triangle_s", p.render_triangle},
                       {"render_fragment_s", p.render_fragment},
                       {"query_setup_s", p.query_setup},
                       {"query_fragment_s", p.query_fragment},
                       {"query_latency_s", p.query_latency},
                       {"query_overhead_s", p.query_overhead},
                       {"poll_s", p.poll},
                       {"queries_in_flight", std::min(nq, 1024.0)},
                       {"polls_used", poll}});
  }
  return 0;
}

}  // namespace

void addCalibrateCommand(CLI::App& app) {
  auto o = std::make_shared<CalibrateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate",
      "measure the hardware parameters of nohc's cost model (NOHC Table 2) and the costs of "
      "auto's (a flush, a pixel read, a box test, a triangle, a draw, a query; per source)");
  addNumber(*cmd, "--size", o->size, closed(16u, 4096u), "framebuffer side in pixels");
  addNumber(*cmd, "--repeats", o->repeats, closed(1u, 1000u), "runs per time (the median is kept)");
  cmd->add_option("--json", o->json, "write the parameters as JSON");
  cmd->add_option("--costs", o->costs,
                  "write the auto method's cost model, per depth source, as a file that walk, "
                  "bench and view (--costs) and loadCullerCosts() read");
  cmd->add_option("--platform", o->walk.platform, "EGL platform: auto, surfaceless or device");
  addLlvmpipeThreadsOption(*cmd, o->walk.lp_threads, "llvmpipe raster threads (LP_NUM_THREADS)");
  cmd->final_callback([o] { throw CLI::RuntimeError(runCalibrate(*o)); });
}

}  // namespace logrid::samples
