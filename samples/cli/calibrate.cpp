// logrid calibrate: the hardware parameters of Guthe et al.'s cost model (NOHC §3.2,
// Table 2) measured on this machine's renderer, as the nohc method measures them at
// start-up (zread/calibration.hpp), with what nohc derives from them (§4.3).
#include <cmath>
#include <cstdio>
#include <memory>

#include "cli/commands.hpp"
#include "cli/machine.hpp"
#include "cli/option_checks.hpp"
#include "cli/options.hpp"
#include "cli/report.hpp"
#include "logrid/zread/calibration.hpp"

namespace logrid::samples {
namespace {

struct CalibrateOptions {
  WalkOptions walk;  // --platform, --lp-threads
  std::uint32_t size = 512;
  std::uint32_t repeats = 5;
  std::string json;
};

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
  if (!o.json.empty()) {
    writeJson(o.json, {{"machine", machineInfo(context)},
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
      "calibrate", "measure the hardware parameters of nohc's cost model (NOHC Table 2)");
  addNumber(*cmd, "--size", o->size, closed(16u, 4096u), "framebuffer side in pixels");
  addNumber(*cmd, "--repeats", o->repeats, closed(1u, 1000u), "runs per time (the median is kept)");
  cmd->add_option("--json", o->json, "write the parameters as JSON");
  cmd->add_option("--platform", o->walk.platform, "EGL platform: auto, surfaceless or device");
  addLlvmpipeThreadsOption(*cmd, o->walk.lp_threads, "llvmpipe raster threads (LP_NUM_THREADS)");
  cmd->final_callback([o] { throw CLI::RuntimeError(runCalibrate(*o)); });
}

}  // namespace logrid::samples
