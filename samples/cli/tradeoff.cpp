#include "cli/tradeoff.hpp"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "cli/common.hpp"
#include "cli/progress.hpp"
#include "cli/report.hpp"

namespace logrid::samples {
namespace {

struct Setting {
  std::string label;
  GridApproximation approximation;
  double budget_ms = 0;  // CullerDesc::budget_ms: the culler sets the knobs itself
};

// The sweep: each knob alone over a range, two combinations, then each budget.
std::vector<Setting> settings(const std::vector<double>& budgets_ms) {
  std::vector<Setting> out{{"conservative", {}}};
  for (std::uint32_t n : {1u, 4u, 16u, 64u, 256u}) {
    GridApproximation a;
    a.visible_pixels = n;
    out.push_back({"visible-pixels " + std::to_string(n), a});
  }
  for (float f : {0.01f, 0.05f, 0.1f, 0.25f}) {
    GridApproximation a;
    a.full_free_fraction = f;
    char label[48];
    std::snprintf(label, sizeof label, "full-fraction %.2f", double(f));
    out.push_back({label, a});
  }
  for (std::uint32_t k : {2u, 4u, 8u}) {
    GridApproximation a;
    a.row_stride = k;
    out.push_back({"row-stride " + std::to_string(k), a});
  }
  GridApproximation mild;
  mild.visible_pixels = 4;
  mild.row_stride = 2;
  out.push_back({"visible-pixels 4 + row-stride 2", mild});
  GridApproximation strong;
  strong.visible_pixels = 64;
  strong.full_free_fraction = 0.1f;
  strong.row_stride = 4;
  out.push_back({"visible-pixels 64 + full-fraction 0.10 + row-stride 4", strong});
  for (double b : budgets_ms) out.push_back({"budget " + formatFixed(b, 1) + " ms", {}, b});
  return out;
}

// Image error of one frame against the full render.
struct ImageError {
  double differing = 0;  // pixels whose colour differs at all
  double mse = 0;        // mean squared error over channels, values in 0..1
};

ImageError compareImages(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                         std::uint32_t width, std::uint32_t height) {
  namespace OIIO = OIIO_NAMESPACE;
  const OIIO::ImageSpec spec(int(width), int(height), 4, OIIO::TypeDesc::UINT8);
  const OIIO::ImageBuf ia(spec, const_cast<std::uint8_t*>(a.data()));
  const OIIO::ImageBuf ib(spec, const_cast<std::uint8_t*>(b.data()));
  // A threshold below one 8-bit step: any change of any channel fails the pixel.
  const OIIO::ImageBufAlgo::CompareResults r =
      OIIO::ImageBufAlgo::compare(ia, ib, 0.5f / 255.0f, 0.5f / 255.0f);
  // (CompareResults::error only says that some pixel failed the threshold.)
  return {double(r.nfail), r.rms_error * r.rms_error};
}

struct Outcome {
  std::string label;
  GridApproximation approximation;
  double budget_ms = 0;
  double ms = 0;
  double p95_ms = 0;                // 95th percentile of the per-frame medians
  std::size_t frames_over = 0;      // frames whose median is over budget_ms (budgets only)
  double spread = 0;
  double pixels_read = 0;
  std::int64_t missed = 0;  // visible objects not drawn, summed over frames
  std::int64_t visible = 0;
  std::size_t frames_with_misses = 0;
  double differing = 0;  // per frame, average
  double psnr = 0;       // from the mean squared error over all frames; inf if identical
  double worst_differing = 0;
  double time_vs_conservative = 0;
  bool pareto = false;  // no other setting at least as good on time and differing pixels
};

// Every setting's images against the full render (every object in the frustum drawn),
// frame by frame, untimed: differing pixels (average and worst frame) and PSNR.
void compareWithFullRender(const LoadedScene& scene, const WalkOptions& so,
                           const std::vector<Measured>& measured, std::vector<Outcome>& outcomes) {
  WalkOptions full = so;
  full.method = "vfc";
  FrameRunner reference(scene.prepared, *scene.renderer, runConfig(full, scene.prepared));
  std::vector<std::unique_ptr<FrameRunner>> runners;
  for (const Measured& m : measured) {
    RunConfig c = m.result.config;
    c.verify = false;
    runners.push_back(std::make_unique<FrameRunner>(scene.prepared, *scene.renderer, c));
  }
  const std::size_t frames = measured.front().result.config.frames;
  std::vector<double> mse_sum(measured.size(), 0);
  Progress progress("tradeoff " + scene.prepared.name + " images", frames);
  for (std::size_t f = 0; f < frames; ++f) {
    reference.renderFrame(f);
    const std::vector<std::uint8_t> truth = reference.readColor();
    for (std::size_t s = 0; s < measured.size(); ++s) {
      runners[s]->renderFrame(f);
      const ViewSettings& view = runners[s]->config().view;
      const ImageError e = compareImages(truth, runners[s]->readColor(), view.width, view.height);
      outcomes[s].differing += e.differing / double(frames);
      outcomes[s].worst_differing = std::max(outcomes[s].worst_differing, e.differing);
      mse_sum[s] += e.mse;
    }
    progress.update(f + 1, 0);
  }
  progress.finish();
  for (std::size_t s = 0; s < measured.size(); ++s) {
    const double mse = mse_sum[s] / double(frames);
    outcomes[s].psnr = mse > 0 ? 10.0 * std::log10(1.0 / mse) : INFINITY;
  }
}

// The Pareto front over (time, differing pixels): nothing else is at least as good on
// both and better on one.
void markPareto(std::vector<Outcome>& outcomes) {
  for (Outcome& o : outcomes) {
    o.pareto = true;
    for (const Outcome& p : outcomes) {
      if (&p != &o && p.ms <= o.ms && p.differing <= o.differing &&
          (p.ms < o.ms || p.differing < o.differing)) {
        o.pareto = false;
      }
    }
  }
}

std::vector<Outcome> outcomesOf(const std::vector<Measured>& measured,
                                const std::vector<Setting>& sweep) {
  std::vector<Outcome> outcomes(measured.size());
  const double log_ms = measured.front().result.avg_ms();
  for (std::size_t s = 0; s < measured.size(); ++s) {
    Outcome& o = outcomes[s];
    const FrameAverages& a = measured[s].frames;
    o.label = sweep[s].label;
    o.approximation = sweep[s].approximation;
    o.budget_ms = sweep[s].budget_ms;
    o.ms = measured[s].result.avg_ms();
    std::vector<double> frame_ms = measured[s].result.frame_ms;
    std::sort(frame_ms.begin(), frame_ms.end());
    if (!frame_ms.empty()) {
      o.p95_ms = frame_ms[std::min(frame_ms.size() - 1, std::size_t(0.95 * double(frame_ms.size())))];
    }
    for (double ms : frame_ms) o.frames_over += o.budget_ms > 0 && ms > o.budget_ms;
    o.spread = measured[s].result.spread();
    o.time_vs_conservative = log_ms > 0 ? o.ms / log_ms : 0;
    o.missed = a.missed;
    o.visible = a.visible;
    o.frames_with_misses = a.frames_with_misses;
    o.pixels_read = a.pixels_read;
  }
  return outcomes;
}

void writeOutcomes(std::ostream& md, const std::vector<Outcome>& outcomes) {
  writeTable<Outcome>(
      md,
      {{"setting", "---", [](const Outcome& o) { return o.label; }},
       {"ms/frame", "--:", [](const Outcome& o) { return formatFixed(o.ms); }},
       {"p95 ms", "--:", [](const Outcome& o) { return formatFixed(o.p95_ms); }},
       {"frames over budget", "--:",
        [](const Outcome& o) {
          return o.budget_ms > 0 ? std::to_string(o.frames_over) : std::string("–");
        }},
       {"× conservative",
        "--:", [](const Outcome& o) { return formatFixed(o.time_vs_conservative); }},
       {"pixels read", "--:", [](const Outcome& o) { return formatFixed(o.pixels_read, 0); }},
       {"missed objects (frames)", "--:",
        [](const Outcome& o) {
          return std::to_string(o.missed) + " of " + std::to_string(o.visible) + " (" +
                 std::to_string(o.frames_with_misses) + ")";
        }},
       {"differing pixels/frame",
        "--:", [](const Outcome& o) { return formatFixed(o.differing, 1); }},
       {"worst frame", "--:", [](const Outcome& o) { return formatFixed(o.worst_differing, 0); }},
       {"PSNR dB",
        "--:", [](const Outcome& o) { return std::isinf(o.psnr) ? "∞" : formatFixed(o.psnr, 1); }},
       {"Pareto", ":-:", [](const Outcome& o) { return o.pareto ? "●" : ""; }}},
      outcomes);
}

nlohmann::json outcomeJson(const Outcome& o) {
  return {{"label", o.label},
          {"visible_pixels", o.approximation.visible_pixels},
          {"full_free_fraction", o.approximation.full_free_fraction},
          {"row_stride", o.approximation.row_stride},
          {"budget_ms", o.budget_ms},
          {"avg_frame_ms", o.ms},
          {"p95_frame_ms", o.p95_ms},
          {"frames_over_budget", o.frames_over},
          {"spread", o.spread},
          {"time_vs_conservative", o.time_vs_conservative},
          {"avg_read_pixels", o.pixels_read},
          {"missed_visible_objects", o.missed},
          {"visible_objects", o.visible},
          {"frames_with_misses", o.frames_with_misses},
          {"avg_differing_pixels", o.differing},
          {"worst_differing_pixels", o.worst_differing},
          {"psnr_db", std::isinf(o.psnr) ? nlohmann::json(nullptr) : nlohmann::json(o.psnr)},
          {"pareto", o.pareto}};
}

constexpr const char* kIntro =
    "Each approximate knob of `CullerDesc::approximation` (log/include/logrid/culler.hpp) "
    "with log-state, on the same frames as the conservative grid (interleaved, medians "
    "over repetitions). Error is measured against the full render (every object in the "
    "frustum drawn): objects the oracle found visible but the method did not draw, pixels "
    "whose colour differs, and PSNR (OpenImageIO `compare`; ∞ when every frame is "
    "identical). The Pareto front holds the settings no other setting beats on both time "
    "and differing pixels. A `budget B ms` row is log-state with `--budget-ms B` "
    "(CullerDesc::budget_ms): the culler moves along the approximate knobs of its setting "
    "(docs/BUDGET.md) to meet B and back to exact when there is time; its frames over "
    "budget count the per-frame medians "
    "above B, and its image error comes from a second, untimed pass in which the "
    "controller chooses again from that pass's own frame times.\n";

}  // namespace

int runTradeoff(const ExperimentOptions& options, const std::vector<double>& budgets_ms) {
  ExperimentOptions checked = options;
  checked.verify = true;  // the objects each setting misses are its error
  Experiment e(checked, "bench --tradeoff", "logrid: speed for accuracy", kIntro);
  e.report()["scenes"] = nlohmann::json::array();
  const std::vector<Setting> sweep = settings(budgets_ms);
  std::vector<Variant> variants;
  for (const Setting& s : sweep) {
    variants.push_back({s.label, [s](WalkOptions& o) {
                          o.approximation = s.approximation;
                          o.budget_ms = s.budget_ms;
                        }});
  }
  bool conservative_missed = false;
  for (const std::string& scene_name : options.scenes) {
    WalkOptions so = e.sceneOptions(scene_name);
    so.size = options.sizes.front();
    so.method = "log-state";
    const LoadedScene scene = e.load(so, variants);
    const std::string name = scene.prepared.name;
    const std::vector<Measured> measured = e.run(scene, so, variants, "tradeoff " + name);
    std::vector<Outcome> outcomes = outcomesOf(measured, sweep);
    compareWithFullRender(scene, so, measured, outcomes);
    markPareto(outcomes);
    if (outcomes.front().missed > 0) conservative_missed = true;

    e.md() << "\n## " << name << " " << so.size << "\n\n"
           << measured.front().result.config.frames << " frames, " << options.repeat
           << " repetitions, tile " << so.tile << ", " << scene.prepared.triangles
           << " triangles (scale " << so.scale << "); log-state with lookahead " << so.lookahead
           << (so.coherence ? " and temporal coherence" : "") << ", reader " << so.reader
           << ".\n\n";
    writeOutcomes(e.md(), outcomes);
    nlohmann::json scene_json = scene.describe();
    scene_json["size"] = so.size;
    scene_json["settings"] = nlohmann::json::array();
    for (const Outcome& o : outcomes) scene_json["settings"].push_back(outcomeJson(o));
    if (!options.plots.empty()) {
      std::vector<PlotPoint> points;
      for (const Outcome& o : outcomes) {
        points.push_back({o.differing, o.time_vs_conservative, o.label, o.pareto});
      }
      const std::string stem = "tradeoff_" + name + "_" + so.size;
      plotPoints(e.plotStem(stem), name + " " + so.size + ": time vs error",
                 "pixels differing from the full render, per frame",
                 "frame time / conservative LOG", points, false);
      const std::string image = e.plotImage("Pareto plot", stem);
      if (!image.empty()) e.md() << "\n" << image << "\n";
    }
    e.report()["scenes"].push_back(std::move(scene_json));
  }
  return e.finish(conservative_missed
                      ? "bench --tradeoff: the conservative setting missed visible objects: a bug"
                      : "");
}

}  // namespace logrid::samples
