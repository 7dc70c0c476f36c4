#include "auto_policy.hpp"

#include <algorithm>
#include <iterator>

#include "subtree_loads.hpp"

namespace logrid::detail {
namespace {

// How fast the outlook follows the frames (weight of the newest frame).
constexpr double kOutlookRate = 0.3;

double modelledSeconds(const CullerCosts& c, const FrameStats& s) {
  return double(s.flushes) * c.flush_s + double(s.pixels_read) * c.pixel_s +
         double(s.boxes_tested + s.boxes_untested) * c.box_test_s +
         double(s.triangles_drawn) * c.triangle_s + double(s.objects_drawn) * c.draw_s +
         double(s.queries) * c.query_s;
}

std::size_t lookaheadIndex(std::uint32_t k) {
  const auto& ks = AutoPolicy::kLookaheads;
  const auto it = std::find(std::begin(ks), std::end(ks), k);
  return it == std::end(ks) ? 0 : std::size_t(it - std::begin(ks));
}

}  // namespace

double expectedTestSeconds(const CullerCosts& costs, const TestOutlook& o, double rect_pixels) {
  return costs.box_test_s + o.flushes_per_test * costs.flush_s +
         o.read_share * rect_pixels * costs.pixel_s;
}

double drawSeconds(const CullerCosts& costs, const NodeLoad& load) {
  return load.triangles * costs.triangle_s + load.objects * costs.draw_s;
}

bool testPays(const CullerCosts& costs, const TestOutlook& outlook, const NodeLoad& load,
              double rect_pixels) {
  const double p = std::max(kMinOccludedFraction, std::min(1.0, outlook.occluded_fraction));
  return p * drawSeconds(costs, load) >= expectedTestSeconds(costs, outlook, rect_pixels);
}

AutoPolicy::AutoPolicy() {
  // Near the fastest exact settings of the benchmarks (docs/TRAVERSAL.md: the forest's
  // log-zfar at K = 16 is within 1 % of its best); the probes move from there.
  current_.method = Method::LogZfar;
  current_.lookahead = 16;
  current_.temporal_coherence = false;
  frame_ = current_;
  // Before any frame: a test is taken to flush once per batch of K boxes, read its whole
  // rectangle and find a box hidden one time in four.
  outlook_.flushes_per_test = 1.0 / current_.lookahead;
  outlook_.read_share = 1;
  outlook_.occluded_fraction = 0.25;
}

FrameSetting AutoPolicy::neighbour(std::uint32_t which) const {
  FrameSetting n = current_;
  const std::size_t k = lookaheadIndex(current_.lookahead);
  const std::size_t last = std::size(kLookaheads) - 1;
  switch (which % 4) {
    case 0: n.lookahead = kLookaheads[std::min(k + 1, last)]; break;
    case 1: n.lookahead = kLookaheads[k > 0 ? k - 1 : 0]; break;
    case 2: n.temporal_coherence = !n.temporal_coherence; break;
    default:
      n.method = current_.method == Method::LogState ? Method::LogZfar : Method::LogState;
      break;
  }
  return n;
}

FrameSetting AutoPolicy::beginFrame(const Hierarchy& hierarchy) {
  loadSubtrees(hierarchy);
  frame_ = current_;
  frame_.probe = false;
  ++since_probe_;
  if (const std::optional<std::uint32_t> which = dueProbe()) {
    since_probe_ = 0;
    probed_ = *which;
    frame_ = neighbour(*which);
    frame_.probe = true;
  }
  return frame_;
}

std::optional<std::uint32_t> AutoPolicy::dueProbe() {
  if (!have_base_ || trial_) return std::nullopt;
  // K at the ladder's end has one neighbour fewer.
  const auto differs = [this](std::uint32_t which) {
    const FrameSetting n = neighbour(which);
    return n.lookahead != current_.lookahead || n.method != current_.method ||
           n.temporal_coherence != current_.temporal_coherence;
  };
  // Out of turn: once a frame has run the current setting since the last probe (the
  // frame after a probe judges it).
  if (out_of_turn_ && since_probe_ >= 2) {
    const std::uint32_t which = *out_of_turn_;
    out_of_turn_.reset();
    if (differs(which)) return which;
  }
  if (since_probe_ < probe_period_) return std::nullopt;
  for (std::uint32_t tries = 0; tries < kNeighbours; ++tries) {
    const std::uint32_t which = next_neighbour_++ % kNeighbours;
    if (differs(which)) return which;
  }
  return std::nullopt;
}

void AutoPolicy::noteViews(const FrameStats& stats) {
  const bool first = frames_ == 1;
  // Under coherence last frame's nodes are drawn first and their own tests then find them
  // visible: the share says nothing about the views there.
  if (first || stats.setting.temporal_coherence || stats.visible_leaves == 0) return;
  const double kept = double(stats.visible_kept) / double(stats.visible_leaves);
  kept_share_ = kept_share_ < 0 ? kept : kept_share_ + kOutlookRate * (kept - kept_share_);
}

void AutoPolicy::endFrame(const FrameStats& stats, const CullerCosts& costs) {
  ++frames_;
  noteViews(stats);
  const double w = outlook_seen_ ? kOutlookRate : 1.0;
  if (stats.boxes_tested > 0) {
    const double flushes = double(stats.flushes) / double(stats.boxes_tested);
    outlook_.flushes_per_test += w * (flushes - outlook_.flushes_per_test);
    if (rect_pixels_ > 0) {
      const double share = double(stats.pixels_read) / rect_pixels_;
      outlook_.read_share += w * (share - outlook_.read_share);
    }
    outlook_seen_ = true;
  }
  if (evidence_ > 0) {
    const double occluded = double(hidden_) / double(evidence_);
    outlook_.occluded_fraction += kOutlookRate * (occluded - outlook_.occluded_fraction);
  }
  rect_pixels_ = 0;
  evidence_ = hidden_ = 0;
  if (stats.triangles_drawn > 0 && stats.seconds > 0) {
    const double rest = stats.seconds - double(stats.flushes) * costs.flush_s -
                        double(stats.pixels_read) * costs.pixel_s -
                        double(stats.boxes_tested + stats.boxes_untested) * costs.box_test_s -
                        double(stats.queries) * costs.query_s;
    const double now = std::max(0.0, rest) / double(stats.triangles_drawn);
    observed_triangle_s_ = observed_triangle_s_ > 0
                               ? observed_triangle_s_ + kOutlookRate * (now - observed_triangle_s_)
                               : now;
  }
  // Frames are compared by their counts under one set of costs: a frame is not judged by
  // costs that its own time (a probe's first coherent frame, a hitch) has just moved
  // while the frame it is compared with was judged by the older ones. A probe and the
  // frames on both sides of it are all modelled with the costs as they stood at the
  // probe (the estimate does not learn from probes; it does from the frame after, whose
  // own time would otherwise judge it: on the loaded 2-core VM one such frame moved the
  // city's modelled frame by a fifth). (Not with effective()'s triangle cost: what it
  // adds, the frame's fixed cost spread over its triangles, would charge coherence on the
  // city for triangles it does not pay.)
  const double seconds = modelledSeconds(costs, stats);
  if (frame_.probe) {
    // A candidate if it models cheaper than the frame before it; adopted only if it is
    // also cheaper than the frame after it (the current setting again). On frames far
    // apart the view changes more than settings differ, and one comparison would adopt a
    // probe for falling on a cheaper view.
    if (seconds < (1.0 - kSwitchMargin) * modelledSeconds(costs, base_frame_)) {
      candidate_ = frame_;
      candidate_->probe = false;
      candidate_frame_ = stats;
      candidate_neighbour_ = probed_;
      candidate_costs_ = costs;
    } else {
      probeLost();
    }
    return;
  }
  if (frames_ > 1) noteMeasured(stats.seconds);  // a culler's first frame sets up
  if (candidate_) {
    const bool wins = modelledSeconds(candidate_costs_, candidate_frame_) <
                      (1.0 - kSwitchMargin) * modelledSeconds(candidate_costs_, stats);
    const FrameSetting candidate = *candidate_;
    candidate_.reset();
    if (wins) {
      adopt(candidate);
      return;
    }
    probeLost();
  }
  if (trial_) judgeTrial(stats.seconds);
  if (!current_.temporal_coherence && !coherence_offered_ && !out_of_turn_ &&
      kept_share_ >= kCoherentViews) {
    out_of_turn_ = kCoherence;  // the views are coherent: try drawing last frame's first
    coherence_offered_ = true;
  }
  base_frame_ = stats;
  have_base_ = true;
  const double settled = modelledSeconds(costs, settled_frame_);
  if (probe_period_ > kProbePeriod &&
      (seconds > kSceneChange * settled || seconds * kSceneChange < settled)) {
    probe_period_ = kProbePeriod;  // the scene changed since the setting settled
    lost_probes_ = 0;
  }
}

void AutoPolicy::adopt(const FrameSetting& next) {
  const FrameSetting previous = current_;
  current_ = next;
  next_neighbour_ = 0;
  base_frame_ = candidate_frame_;
  probe_period_ = kProbePeriod;
  lost_probes_ = 0;
  // A step of K that won: the next step the same way, out of turn; coherence may be
  // offered again at the new setting.
  const bool k_step =
      candidate_neighbour_ == kLookaheadUp || candidate_neighbour_ == kLookaheadDown;
  out_of_turn_.reset();
  if (k_step) out_of_turn_ = candidate_neighbour_;
  coherence_offered_ = false;
  // Where the views are coherent, the frames' own time before and after the switch
  // compares the settings on much the same view: a trial.
  trial_.reset();
  if (kept_share_ >= kCoherentViews && measured_count_ >= kTrialBase) {
    const std::size_t n = std::min<std::size_t>(measured_count_, measured_.size());
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i) sum += measured_[i];
    if (sum > 0) trial_ = Trial{previous, candidate_neighbour_, sum / double(n)};
  }
  measured_count_ = 0;
}

void AutoPolicy::noteMeasured(double seconds) {
  measured_[measured_count_++ % measured_.size()] = seconds;
}

void AutoPolicy::judgeTrial(double seconds) {
  Trial& t = *trial_;
  if (t.skipped < kTrialSkip) {  // a setting's first frames may pay once (coherence's set)
    ++t.skipped;
    return;
  }
  t.sum_s += seconds;
  if (++t.frames < kTrialFrames) return;
  const Trial done = t;
  trial_.reset();
  if (done.sum_s / double(done.frames) <= (1.0 + kSwitchMargin) * done.before_s) return;
  // The frames' own time does not bear the model out: back to the setting before.
  current_ = done.previous;
  measured_count_ = 0;
  since_probe_ = 0;
  out_of_turn_.reset();
  if (done.neighbour == kCoherence) coherence_offered_ = true;
  ++reverts_;
  probeLost();
}

void AutoPolicy::probeLost() {
  if (++lost_probes_ == kNeighbours) {  // every neighbour lost in turn
    probe_period_ = std::min(kMaxProbePeriod, 2 * probe_period_);
    lost_probes_ = 0;
    settled_frame_ = base_frame_;
  }
}

void AutoPolicy::noteAnswer(double rect_pixels, bool occluded, bool evidence) {
  rect_pixels_ += rect_pixels;
  if (!evidence) return;
  ++evidence_;
  hidden_ += occluded;
}

NodeLoad AutoPolicy::load(NodeId node) const {
  const auto it = loads_.find(node);
  return it == loads_.end() ? NodeLoad{} : it->second;
}

bool AutoPolicy::worthTesting(NodeId node, double rect_pixels, const CullerCosts& costs) const {
  // Before a frame has shown what tests and triangles cost here (the prior's triangle is
  // far cheaper than a scene's: the first frame would draw most leaves untested), and for
  // a node of unknown load: test, as every exact method would.
  if (!outlook_seen_) return true;
  const auto it = loads_.find(node);
  if (it == loads_.end()) return true;
  return testPays(effective(costs), outlook_, it->second, rect_pixels);
}

CullerCosts AutoPolicy::effective(const CullerCosts& costs) const {
  CullerCosts c = costs;
  c.triangle_s = std::max(c.triangle_s, observed_triangle_s_);
  return c;
}

void AutoPolicy::loadSubtrees(const Hierarchy& h) {
  if (loads_hierarchy_ == &h && loads_revision_ == h.revision() && !loads_.empty()) return;
  loads_.clear();
  loads_hierarchy_ = &h;
  loads_revision_ = h.revision();
  for (const auto& [node, load] : subtreeLoads(h)) {
    loads_[node] = {double(load.triangles), double(load.objects)};
  }
}

}  // namespace logrid::detail
