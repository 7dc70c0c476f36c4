#include "cli/interleaved.hpp"

#include <algorithm>
#include <cassert>
#include <memory>

#include "cli/progress.hpp"
#include "cli/summary.hpp"

namespace logrid::samples {
namespace {

bool sameView(const ViewSettings& a, const ViewSettings& b) {
  return a.width == b.width && a.height == b.height && a.fov_degrees == b.fov_degrees &&
         a.orthographic == b.orthographic && a.near_plane == b.near_plane &&
         a.far_plane == b.far_plane && a.depth.convention == b.depth.convention &&
         a.depth.format == b.depth.format && a.depth.clip_range == b.depth.clip_range;
}

}  // namespace

double ConfigResult::avg_ms() const {
  double sum = 0;
  for (double v : frame_ms) sum += v;
  return frame_ms.empty() ? 0 : sum / double(frame_ms.size());
}

double ConfigResult::spread() const {
  if (repetition_ms.size() < 2) return 0;
  const auto [lo, hi] = std::minmax_element(repetition_ms.begin(), repetition_ms.end());
  const double mid = median(repetition_ms);
  return mid > 0 ? (*hi - *lo) / mid : 0;
}

std::vector<ConfigResult> runInterleaved(const PreparedScene& scene, gl::MeshRenderer& renderer,
                                         const std::vector<RunConfig>& configs, std::size_t repeats,
                                         const std::string& label, std::size_t warmup) {
  assert(repeats >= 1 && !configs.empty() && "runInterleaved: no repetition or configuration");
  const std::size_t frames = configs.front().frames;
  std::vector<std::unique_ptr<FrameRunner>> runners;
  std::vector<ConfigResult> results(configs.size());
  // One ID pass per frame for all configurations with the same view.
  std::vector<std::pair<ViewSettings, std::shared_ptr<OracleCache>>> caches;
  auto cacheFor = [&](const ViewSettings& v) {
    for (auto& [view, cache] : caches) {
      if (sameView(view, v)) return cache;
    }
    caches.emplace_back(v, std::make_shared<OracleCache>());
    return caches.back().second;
  };
  for (std::size_t c = 0; c < configs.size(); ++c) {
    RunConfig timed = configs[c];
    timed.frames = frames;
    runners.push_back(std::make_unique<FrameRunner>(scene, renderer, timed));
    runners.back()->shareOracle(cacheFor(timed.view));
    results[c].config = timed;
  }
  for (std::size_t w = 0; w < warmup; ++w) {
    for (auto& runner : runners) runner->renderFrame(w * frames / std::max<std::size_t>(warmup, 1));
  }
  std::vector<std::vector<double>> times(configs.size(), std::vector<double>(frames * repeats));
  Progress progress(label, frames * repeats);
  for (std::size_t rep = 0; rep < repeats; ++rep) {
    for (std::size_t f = 0; f < frames; ++f) {
      double round_ms = 0;
      for (std::size_t c = 0; c < runners.size(); ++c) {
        // Only the first repetition pays for the oracle check (it is not timed anyway).
        FrameRecord rec = runners[c]->renderFrame(f);
        times[c][rep * frames + f] = rec.ms;
        round_ms += rec.ms;
        if (rep == 0) results[c].records.push_back(std::move(rec));
      }
      progress.update(rep * frames + f + 1, round_ms);
    }
    if (rep == 0) {
      // Later repetitions skip the ID pass: rebuild runners without verification.
      for (std::size_t c = 0; c < runners.size(); ++c) {
        if (!configs[c].verify) continue;
        RunConfig quiet = results[c].config;
        quiet.verify = false;
        runners[c] = std::make_unique<FrameRunner>(scene, renderer, quiet);
        runners[c]->shareOracle(cacheFor(quiet.view));
        runners[c]->renderFrame(0);  // warm the new framebuffer's state
      }
    }
  }
  progress.finish();
  for (std::size_t c = 0; c < configs.size(); ++c) {
    ConfigResult& r = results[c];
    for (std::size_t f = 0; f < frames; ++f) {
      std::vector<double> samples;
      for (std::size_t rep = 0; rep < repeats; ++rep) samples.push_back(times[c][rep * frames + f]);
      r.frame_ms.push_back(median(samples));
      r.frame_ms_low.push_back(*std::min_element(samples.begin(), samples.end()));
      r.frame_ms_high.push_back(*std::max_element(samples.begin(), samples.end()));
    }
    for (std::size_t rep = 0; rep < repeats; ++rep) {
      double sum = 0;
      for (std::size_t f = 0; f < frames; ++f) sum += times[c][rep * frames + f];
      r.repetition_ms.push_back(sum / double(frames));
    }
  }
  return results;
}

}  // namespace logrid::samples
