#include "cli/tradeoff.hpp"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

#include "cli/experiment.hpp"
#include "cli/plot.hpp"
#include "cli/report.hpp"
#include "logrid/error.hpp"

namespace logrid::samples {
namespace {

struct Setting {
  std::string label;
  GridApproximation approximation;
};

// The sweep: each knob alone over a range, and two combinations.
std::vector<Setting> settings() {
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
  double ms = 0;
  double spread = 0;
  double pixels_read = 0;
  std::int64_t missed = 0;  // visible objects not drawn, summed over frames
  std::int64_t visible = 0;
  std::size_t frames_with_misses = 0;
  double differing = 0;  // per frame, average
  double psnr = 0;       // from the mean squared error over all frames; inf if identical
  double worst_differing = 0;
};

}  // namespace

int runTradeoff(const WalkOptions& base, const std::vector<std::string>& scenes,
                const std::vector<std::string>& sizes, double forest_scale, double city_scale,
                std::size_t repeats, const std::string& markdown, const std::string& json,
                const std::string& plots) {
  if (scenes.empty() || sizes.empty()) {
    throw Error(ErrorCode::InvalidArgument, "bench --tradeoff: --scenes and --sizes need an entry");
  }
  if (!plots.empty()) std::filesystem::create_directories(plots);
  gl::Context context(contextDesc(base));
  const nlohmann::json machine = machineInfo(context);
  const std::vector<Setting> sweep = settings();

  std::ostringstream md;
  md << "# logrid: speed for accuracy\n\n"
     << "Machine: " << machineLine(machine) << ".\n\nCommand: `" << commandLine() << "`\n\n"
     << "Each approximate knob of `CullerDesc::approximation` (log/include/logrid/culler.hpp) "
        "with log-state, on the same frames as the conservative grid (interleaved, medians "
        "over repetitions). Error is measured against the full render (every object in the "
        "frustum drawn): objects the oracle found visible but the method did not draw, pixels "
        "whose colour differs, and PSNR (OpenImageIO `compare`; ∞ when every frame is "
        "identical). The Pareto front holds the settings no other setting beats on both time "
        "and differing pixels.\n";
  nlohmann::json report = {
      {"command", commandLine()}, {"machine", machine}, {"scenes", nlohmann::json::array()}};
  bool conservative_missed = false;

  for (const std::string& scene_name : scenes) {
    WalkOptions so = optionsForScene(base, scene_name, forest_scale, city_scale);
    so.size = sizes.front();
    so.method = "log-state";
    LoadedScene scene = loadScene(so);

    std::vector<RunConfig> configs;
    for (const Setting& s : sweep) {
      WalkOptions mo = so;
      mo.approximation = s.approximation;
      mo.verify = true;
      configs.push_back(runConfig(mo, scene.prepared));
    }
    const std::vector<ConfigResult> results = runInterleaved(
        scene.prepared, *scene.renderer, configs, repeats, "tradeoff " + scene.prepared.name);

    // Images: every setting against the full render, frame by frame (untimed).
    WalkOptions full = so;
    full.method = "vfc";
    FrameRunner reference(scene.prepared, *scene.renderer, runConfig(full, scene.prepared));
    std::vector<std::unique_ptr<FrameRunner>> runners;
    for (RunConfig c : configs) {
      c.verify = false;
      runners.push_back(std::make_unique<FrameRunner>(scene.prepared, *scene.renderer, c));
    }
    const std::size_t frames = configs.front().frames;
    std::vector<Outcome> outcomes(sweep.size());
    std::vector<double> mse_sum(sweep.size(), 0);
    Progress progress("tradeoff " + scene.prepared.name + " images", frames);
    for (std::size_t f = 0; f < frames; ++f) {
      reference.renderFrame(f);
      const std::vector<std::uint8_t> truth = reference.readColor();
      for (std::size_t s = 0; s < sweep.size(); ++s) {
        runners[s]->renderFrame(f);
        const ImageError e = compareImages(truth, runners[s]->readColor(), configs[s].view.width,
                                           configs[s].view.height);
        outcomes[s].differing += e.differing / double(frames);
        outcomes[s].worst_differing = std::max(outcomes[s].worst_differing, e.differing);
        mse_sum[s] += e.mse;
      }
      progress.update(f + 1, 0);
    }
    progress.finish();

    const double log_ms = results.front().avg_ms();
    for (std::size_t s = 0; s < sweep.size(); ++s) {
      Outcome& o = outcomes[s];
      o.label = sweep[s].label;
      o.approximation = sweep[s].approximation;
      o.ms = results[s].avg_ms();
      o.spread = results[s].spread();
      for (const FrameRecord& r : results[s].records) {
        o.missed += r.missed;
        o.visible += r.visible;
        o.frames_with_misses += r.missed > 0;
        o.pixels_read += double(r.stats.pixels_read) / double(frames);
      }
      const double mse = mse_sum[s] / double(frames);
      o.psnr = mse > 0 ? 10.0 * std::log10(1.0 / mse) : INFINITY;
    }
    if (outcomes.front().missed > 0) conservative_missed = true;

    // Pareto front over (time, differing pixels): nothing else is at least as good on
    // both and better on one.
    std::vector<PlotPoint> points;
    for (const Outcome& o : outcomes) {
      bool dominated = false;
      for (const Outcome& p : outcomes) {
        if (&p == &o) continue;
        if (p.ms <= o.ms && p.differing <= o.differing &&
            (p.ms < o.ms || p.differing < o.differing))
          dominated = true;
      }
      points.push_back({o.differing, log_ms > 0 ? o.ms / log_ms : 0, o.label, !dominated});
    }

    md << "\n## " << scene.prepared.name << " " << so.size << "\n\n"
       << frames << " frames, " << repeats << " repetitions, tile " << so.tile << ", "
       << scene.prepared.triangles << " triangles (scale " << so.scale << ").\n\n"
       << "| setting | ms/frame | × conservative | pixels read | missed objects (frames) "
          "| differing pixels/frame | worst frame | PSNR dB | Pareto |\n"
       << "|---|--:|--:|--:|--:|--:|--:|--:|:-:|\n";
    nlohmann::json scene_json = scene.describe();
    scene_json["size"] = so.size;
    scene_json["settings"] = nlohmann::json::array();
    for (std::size_t s = 0; s < outcomes.size(); ++s) {
      const Outcome& o = outcomes[s];
      md << "| " << o.label << " | " << formatFixed(o.ms) << " | "
         << formatFixed(log_ms > 0 ? o.ms / log_ms : 0) << " | " << formatFixed(o.pixels_read, 0)
         << " | " << o.missed << " of " << o.visible << " (" << o.frames_with_misses << ") | "
         << formatFixed(o.differing, 1) << " | " << formatFixed(o.worst_differing, 0) << " | "
         << (std::isinf(o.psnr) ? "∞" : formatFixed(o.psnr, 1)) << " | "
         << (points[s].highlight ? "●" : "") << " |\n";
      scene_json["settings"].push_back(
          {{"label", o.label},
           {"visible_pixels", o.approximation.visible_pixels},
           {"full_free_fraction", o.approximation.full_free_fraction},
           {"row_stride", o.approximation.row_stride},
           {"avg_frame_ms", o.ms},
           {"spread", o.spread},
           {"time_vs_conservative", log_ms > 0 ? o.ms / log_ms : 0},
           {"avg_read_pixels", o.pixels_read},
           {"missed_visible_objects", o.missed},
           {"visible_objects", o.visible},
           {"frames_with_misses", o.frames_with_misses},
           {"avg_differing_pixels", o.differing},
           {"worst_differing_pixels", o.worst_differing},
           {"psnr_db", std::isinf(o.psnr) ? nlohmann::json(nullptr) : nlohmann::json(o.psnr)},
           {"pareto", points[s].highlight}});
    }
    if (!plots.empty()) {
      const std::string stem = plots + "/tradeoff_" + scene.prepared.name + "_" + so.size;
      plotPoints(stem, scene.prepared.name + " " + so.size + ": time vs error",
                 "pixels differing from the full render, per frame",
                 "frame time / conservative LOG", points, false);
      if (!markdown.empty())
        md << "\n![Pareto plot](" << linkFrom(markdown, stem + ".png") << ")\n";
    }
    report["scenes"].push_back(std::move(scene_json));
  }
  std::printf("%s", md.str().c_str());
  if (!markdown.empty()) writeText(markdown, md.str());
  if (!json.empty()) writeJson(json, report);
  if (conservative_missed) {
    std::fprintf(stderr,
                 "bench --tradeoff: the conservative setting missed visible objects: a bug\n");
    return 1;
  }
  return 0;
}

}  // namespace logrid::samples
