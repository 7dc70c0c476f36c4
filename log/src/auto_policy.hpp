// The choices of the `auto` method (docs/AUTO.md), apart from the culler's traversal so
// that they can be tested against scripted costs. Internal to logrid::core.
//
// Per node: the reasonability test of near-optimal hierarchical culling (Guthe, Balázs,
// Klein 2006, §4.1) applied to grid tests: a test pays only if the drawing it is expected
// to save, P(occluded) x the seconds to draw the node's subtree, exceeds what the test is
// expected to cost (its share of a flush, and the pixels a test of its rectangle's size
// reads). A node whose test does not pay is treated as visible without a test (drawn, or
// opened and its children considered): always conservative. Until a frame has shown what
// tests and drawing cost here, every node is tested, as the fixed methods do.
//
// Per frame: the exact setting (grid method, lookahead K, temporal coherence) is kept
// while it models cheapest; one frame in a probe period tries one neighbouring setting
// (K x4 or /4, coherence flipped, the other grid variant), and the neighbour is adopted
// when its frame models at least kSwitchMargin cheaper than the frames before and after
// it, all three modelled with the costs as they stood at the probe (the hysteresis that keeps
// settings from flickering, and from following a view that happened to be cheaper). The period
// starts at kProbePeriod and doubles, up to kMaxProbePeriod, each time every neighbour
// in turn has lost (the setting is a local optimum and a probe is a frame paid for
// nothing); it starts again at kProbePeriod when a probe wins or when the frames'
// modelled time moves by more than kSceneChange from where the period last doubled (the
// scene changed: look around again).
//
// Two probes come out of turn, as soon as a frame has run the current setting since the
// last probe (the climb to a distant optimum takes a few frames instead of a few probe
// periods): after a step of K won, the next step the same way (K x4 won, so K x16 may
// too); and while coherence is off, coherence once the views are seen to be coherent:
// at least kCoherentViews of the visible nodes with objects were visible the frame before
// too (what temporal coherence draws first without waiting). Again after each win.
//
// The model judges by counts; where the views are coherent the frames' own time can
// check it, since frames before and after a switch see much the same. After a switch
// there, no probe runs for a trial of kTrialFrames frames (after kTrialSkip, which may
// pay once for the switch); if they took on average more than (1 + kSwitchMargin) times
// the frames before the probe (up to kTrialFrames of them, at least kTrialBase), the
// setting goes back and the switch counts as a lost probe. (On the loaded 2-core VM the
// city's coherent settings ran 1.2x log-zfar:16's frame time while modelling cheaper;
// on a quiet one 0.6x.)
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "logrid/costs.hpp"
#include "logrid/hierarchy.hpp"
#include "logrid/method.hpp"
#include "logrid/stats.hpp"

namespace logrid::detail {

// What the culler has seen its tests do over the recent frames.
struct TestOutlook {
  double flushes_per_test = 1;   // renderer waits per box tested
  double read_share = 1;         // depth pixels read per pixel of the tested rectangles
  double occluded_fraction = 0;  // share of the answers that were evidence and occluded
};

// What drawing a node's subtree untested would draw.
struct NodeLoad {
  double triangles = 0;
  double objects = 0;
};

// The least occlusion probability a test is granted, so that large subtrees stay tested
// where nothing was hidden lately and testing comes back where it pays again. (At 0.02
// a leaf's test still paid on the sparse forest, where nothing is hidden.)
inline constexpr double kMinOccludedFraction = 0.005;

// A test of a box whose rectangle on screen covers `rect_pixels`.
double expectedTestSeconds(const CullerCosts& costs, const TestOutlook& outlook,
                           double rect_pixels);
double drawSeconds(const CullerCosts& costs, const NodeLoad& load);
// The reasonability test: true when testing the node is expected to cost less than the
// drawing it may save.
bool testPays(const CullerCosts& costs, const TestOutlook& outlook, const NodeLoad& load,
              double rect_pixels);

class AutoPolicy {
 public:
  static constexpr std::uint32_t kProbePeriod = 8;
  static constexpr std::uint32_t kMaxProbePeriod = 64;
  static constexpr std::uint32_t kNeighbours = 4;
  static constexpr double kSceneChange = 1.5;
  static constexpr double kSwitchMargin = 0.10;
  static constexpr double kCoherentViews = 0.8;
  static constexpr std::uint32_t kTrialFrames = 6;
  static constexpr std::uint32_t kTrialSkip = 1;
  static constexpr std::uint32_t kTrialBase = 2;
  // The neighbours, in the order probed in turn.
  enum Neighbour : std::uint32_t { kLookaheadUp, kLookaheadDown, kCoherence, kVariant };
  // The lookaheads auto chooses among.
  static constexpr std::uint32_t kLookaheads[] = {1, 4, 16, 64, 256};

  AutoPolicy();

  // The setting of the next frame (a probe once per probePeriod() frames).
  FrameSetting beginFrame(const Hierarchy& hierarchy);
  // Is testing `node`, whose rectangle covers `rect_pixels`, expected to pay (its
  // subtree's load from the hierarchy of the last beginFrame)?
  bool worthTesting(NodeId node, double rect_pixels, const CullerCosts& costs) const;
  // One test's answer. `evidence`: it says something about what testing saves (an answer
  // from a read, or occluded from what the grid recorded). A box found visible on tiles
  // nothing was drawn on yet (the large nodes near the root, before anything in front of
  // them is drawn) is not: such answers cost nothing and would drag P(occluded) down
  // until the per-node test refused every smaller node. Every answer's rectangle counts
  // toward the read share.
  void noteAnswer(double rect_pixels, bool occluded, bool evidence);
  // What the frame did, with the costs as now estimated.
  void endFrame(const FrameStats& stats, const CullerCosts& costs);

  const TestOutlook& outlook() const { return outlook_; }
  // Seconds per drawn triangle as the frames show it: what is left of a frame's time
  // after its flushes, pixels and tests, over the triangles it drew (0 before a frame
  // that drew any). The per-node test takes the larger of this and the model's
  // triangle_s (effective()): a prior such as NOHC's pixel-sized triangle misses the
  // fragments of a scene's triangles, and drawing is what a test saves.
  double observedTriangleSeconds() const { return observed_triangle_s_; }
  const FrameSetting& current() const { return current_; }
  std::uint32_t probePeriod() const { return probe_period_; }
  // The share of the visible nodes with objects that were visible the frame before, as
  // the recent frames without coherence show it (negative before any such frame).
  double keptShare() const { return kept_share_; }
  // Switches the frames' own time did not bear out, taken back (see above).
  std::uint32_t reverts() const { return reverts_; }
  NodeLoad load(NodeId node) const;

 private:
  FrameSetting neighbour(std::uint32_t which) const;
  // The neighbour of the next probe, if one is due (nullopt: none, or none differs).
  std::optional<std::uint32_t> dueProbe();
  void probeLost();
  void noteViews(const FrameStats& stats);
  void adopt(const FrameSetting& next);
  void noteMeasured(double seconds);
  void judgeTrial(double seconds);
  // `costs` with the larger of its and the observed triangle cost (the per-node test's).
  CullerCosts effective(const CullerCosts& costs) const;
  void loadSubtrees(const Hierarchy& hierarchy);

  FrameSetting current_;
  FrameSetting frame_;             // this frame's (a probe or current_)
  std::uint32_t since_probe_ = 0;  // frames since the last probe (or the first frame)
  std::uint32_t probe_period_ = kProbePeriod;
  std::uint32_t lost_probes_ = 0;  // in a row
  FrameStats settled_frame_;       // the base frame when the period last doubled
  std::uint32_t next_neighbour_ = 0;
  std::uint32_t probed_ = 0;                  // this frame's neighbour, if a probe
  std::optional<std::uint32_t> out_of_turn_;  // probed as soon as a base frame has run
  bool coherence_offered_ = false;            // out of turn, since the last win
  double kept_share_ = -1;
  // The measured seconds of the last frames at the current setting (not probes).
  std::array<double, kTrialFrames> measured_{};
  std::size_t measured_count_ = 0;
  struct Trial {
    FrameSetting previous;
    std::uint32_t neighbour = 0;  // what the switch changed
    double before_s = 0;          // mean measured seconds of the frames before it
    double sum_s = 0;
    std::uint32_t frames = 0;
    std::uint32_t skipped = 0;
  };
  std::optional<Trial> trial_;
  std::uint32_t reverts_ = 0;
  std::uint64_t frames_ = 0;  // ended
  bool have_base_ = false;
  FrameStats base_frame_;  // the last non-probe frame (or the adopted probe)
  // A probe that beat the frame before it, until the frame after it has run.
  std::optional<FrameSetting> candidate_;
  FrameStats candidate_frame_;
  std::uint32_t candidate_neighbour_ = 0;
  CullerCosts candidate_costs_;  // as they stood at the probe: the frame after is judged by them
  TestOutlook outlook_;
  // This frame's noteAnswer()s.
  double rect_pixels_ = 0;
  std::uint64_t evidence_ = 0, hidden_ = 0;
  bool outlook_seen_ = false;
  double observed_triangle_s_ = 0;
  // Subtree loads, for which hierarchy.
  const Hierarchy* loads_hierarchy_ = nullptr;
  std::uint64_t loads_revision_ = 0;
  std::unordered_map<NodeId, NodeLoad> loads_;
};

}  // namespace logrid::detail
