#include "cli/interleaved.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <memory>
#include <vector>

#include "cli/progress.hpp"
#include "cli/summary.hpp"

namespace logrid::samples {
namespace {

bool sameView(const ViewSettings& a, const ViewSettings& b) {
  return a.width == b.width && a.height == b.height && a.fov_degrees == b.fov_degrees &&
         a.orthographic == b.orthographic && a.near_plane == b.near_plane &&
         a.far_plane == b.far_plane && a.depth.convention == b.depth.convention &&
         a.depth.format == b.depth.format && a.depth.clip_range == b.depth.clip_range &&
         a.samples == b.samples && a.cull_back_faces == b.cull_back_faces;
}

// `first`: the first repetition's frame times; `second`: the second's, whose odd frames
// ran with an ID pass of their own and whose even frames with none (runInterleaved).
VerificationCheck verificationCheck(const double* first, const double* second, std::size_t frames) {
  VerificationCheck check;
  // Each frame against its own time in the first repetition: the frames' costs cancel,
  // and the even frames' ratio is the drift between the two repetitions.
  std::vector<double> ratios[2];  // even, odd
  double sums[2][2] = {};         // [even, odd][first, second]
  for (std::size_t f = 0; f < frames; ++f) {
    if (first[f] <= 0) continue;
    ratios[f % 2].push_back(second[f] / first[f]);
    sums[f % 2][0] += first[f], sums[f % 2][1] += second[f];
  }
  if (ratios[0].size() < 2 || ratios[1].size() < 2 || sums[0][1] <= 0) return check;
  const double drift = sums[0][1] / sums[0][0];
  check.measured = true;
  check.verified_ms = sums[1][1] / double(ratios[1].size());
  check.unverified_ms = drift * sums[1][0] / double(ratios[1].size());
  check.difference = check.verified_ms / check.unverified_ms - 1;
  // Twice the standard error of the difference of the two groups' mean ratios, relative
  // to the drift.
  double variance_of_difference = 0;
  for (const std::vector<double>& group : ratios) {
    double mean = 0, squares = 0;
    for (double v : group) mean += v;
    mean /= double(group.size());
    for (double v : group) squares += (v - mean) * (v - mean);
    variance_of_difference += squares / double(group.size() - 1) / double(group.size());
  }
  check.noise = 2 * std::sqrt(variance_of_difference) / drift;
  return check;
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
  std::vector<SceneConfig> on_scene;
  for (const RunConfig& c : configs) on_scene.push_back({&scene, &renderer, c});
  return runInterleaved(on_scene, repeats, label, warmup);
}

std::vector<ConfigResult> runInterleaved(const std::vector<SceneConfig>& subjects,
                                         std::size_t repeats, const std::string& label,
                                         std::size_t warmup) {
  assert(repeats >= 1 && !subjects.empty() && "runInterleaved: no repetition or configuration");
  std::vector<RunConfig> configs;
  for (const SceneConfig& s : subjects) configs.push_back(s.config);
  const std::size_t frames = configs.front().frames;
  std::vector<std::unique_ptr<FrameRunner>> runners;
  std::vector<ConfigResult> results(configs.size());
  // One ID pass per frame for all configurations of one scene with the same view.
  struct Cache {
    const PreparedScene* scene;
    ViewSettings view;
    std::shared_ptr<OracleCache> cache;
  };
  std::vector<Cache> caches;
  auto cacheFor = [&](std::size_t c) {
    const ViewSettings& v = runners[c]->config().view;
    for (const Cache& k : caches) {
      if (k.scene == subjects[c].scene && sameView(k.view, v)) return k.cache;
    }
    caches.push_back({subjects[c].scene, v, std::make_shared<OracleCache>()});
    return caches.back().cache;
  };
  for (std::size_t c = 0; c < configs.size(); ++c) {
    RunConfig timed = configs[c];
    timed.frames = frames;
    runners.push_back(
        std::make_unique<FrameRunner>(*subjects[c].scene, *subjects[c].renderer, timed));
    runners.back()->shareOracle(cacheFor(c));
    results[c].config = timed;
  }
  // Every frame's visible set before anything is timed: the oracle's rows and the first
  // repetition's verification then take it from the cache, and no ID pass runs between
  // timed frames (except the second repetition's, for VerificationCheck). One oracle
  // runner per view, for its ID passes only.
  for (std::size_t c = 0; c < configs.size(); ++c) {
    if (!configs[c].verify && !configs[c].method.oracle()) continue;
    const std::shared_ptr<OracleCache> cache = cacheFor(c);
    if (cache->frames.size() >= frames) continue;  // another configuration's view
    RunConfig passes = results[c].config;
    passes.method = MethodChoice{};
    passes.verify = false;
    passes.images_dir.clear();
    passes.overlay = false;
    FrameRunner ids(*subjects[c].scene, *subjects[c].renderer, passes);
    ids.shareOracle(cache);
    for (std::size_t f = 0; f < frames; ++f) ids.renderFrame(f);
  }
  for (std::size_t w = 0; w < warmup; ++w) {
    for (auto& runner : runners) runner->renderFrame(w * frames / std::max<std::size_t>(warmup, 1));
  }
  std::vector<std::vector<double>> times(configs.size(), std::vector<double>(frames * repeats));
  Progress progress(label, frames * repeats);
  for (std::size_t rep = 0; rep < repeats; ++rep) {
    // The first repetition verifies every frame (records keep its counts), sharing one ID
    // pass per frame; later ones verify none, except that the second runs its odd frames
    // with an ID pass of each configuration's own (after a method's frame, before the
    // oracle's) for VerificationCheck, and its even frames with none at all.
    for (std::size_t f = 0; f < frames; ++f) {
      double round_ms = 0;
      for (std::size_t c = 0; c < runners.size(); ++c) {
        const bool own_pass = rep == 1 && f % 2 == 1 && configs[c].verify;
        runners[c]->setVerify(configs[c].verify && (rep == 0 || own_pass));
        runners[c]->shareOracle(own_pass ? nullptr : cacheFor(c));
        FrameRecord rec = runners[c]->renderFrame(f);
        times[c][rep * frames + f] = rec.ms;
        round_ms += rec.ms;
        if (rep == 0) results[c].records.push_back(std::move(rec));
      }
      progress.update(rep * frames + f + 1, round_ms);
    }
  }
  progress.finish();
  for (std::size_t c = 0; c < configs.size(); ++c) {
    ConfigResult& r = results[c];
    for (std::size_t f = 0; f < frames; ++f) {
      // The frames the second repetition ran with ID passes count only for the check.
      std::vector<double> samples;
      for (std::size_t rep = 0; rep < repeats; ++rep) {
        if (rep != 1 || f % 2 == 0 || !configs[c].verify) {
          samples.push_back(times[c][rep * frames + f]);
        }
      }
      r.frame_ms.push_back(median(samples));
      r.frame_ms_low.push_back(*std::min_element(samples.begin(), samples.end()));
      r.frame_ms_high.push_back(*std::max_element(samples.begin(), samples.end()));
    }
    for (std::size_t rep = 0; rep < repeats; ++rep) {
      double sum = 0;
      for (std::size_t f = 0; f < frames; ++f) sum += times[c][rep * frames + f];
      r.repetition_ms.push_back(sum / double(frames));
    }
    if (configs[c].verify && repeats >= 2) {
      r.verification = verificationCheck(times[c].data(), times[c].data() + frames, frames);
    }
  }
  return results;
}

}  // namespace logrid::samples
