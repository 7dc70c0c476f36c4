// Temporal coherence and lookahead across discontinuities between frames, every frame
// checked against the object-ID oracle. One FrameRunner (one Culler, with what it
// remembers of the last frame) renders a short sequence in which, between two frames:
//
//   Cut         the camera jumps to an unrelated pose (another part of the path, looking
//               elsewhere), and back;
//   Teleport    the eye jumps past the point it looked at, behind the last frame's
//               occluders, looking on and then back at them;
//   Resize      the viewport changes size (odd sizes included) and back;
//   DepthFormat the depth format (D24, D32F) and the convention (standard, reversed)
//               change;
//   Rebuild     the hierarchy is built again in the same object (other node ids);
//   Replace     another hierarchy object is culled, then the first again;
//   RemoveAdd   the objects the last frame drew are removed from the scene (a hierarchy
//               without them, which the ID pass draws too), then added back.
//
// Each with every grid method (MethodInfo::grid) at each of its lookahead and coherence
// settings (log+hwq: each query schedule), and the cpu and pbo readers for some; zero
// misses. Where the hierarchy
// changed, the culler must have dropped its coherent leaves (none drawn first on the next
// frame: FrameStats::coherent_leaves), since its node ids no longer mean the same nodes;
// elsewhere it may keep them (they are projected with the new camera and drawn first,
// which is conservative), and the sequences show that it does.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>

#include "logrid/bvh/bvh.hpp"
#include "oracle_harness.hpp"

namespace logrid::oracle {
namespace {

enum class Kind : std::uint8_t { Cut, Teleport, Resize, DepthFormat, Rebuild, Replace, RemoveAdd };

const char* toString(Kind k) {
  switch (k) {
    case Kind::Cut: return "cut";
    case Kind::Teleport: return "teleport";
    case Kind::Resize: return "resize";
    case Kind::DepthFormat: return "depth_format";
    case Kind::Rebuild: return "rebuild";
    case Kind::Replace: return "replace";
    case Kind::RemoveAdd: return "remove_add";
  }
  return "?";
}

// The city with its DDO octree (for ddo+log), shared with the DDO oracle tests.
SceneKey cityKey() { return sceneKey("city", 0, true); }

// Consecutive frames of the sequences are path frames of a 40-frame walk: close poses.
constexpr std::size_t kPathFrames = 40;

struct Setting {
  samples::MethodChoice method;
  std::string reader = "readpixels";
};

std::string settingName(const Setting& s) { return s.method.name() + "/" + s.reader; }

// Every grid method at each lookahead (1, 4, all) and coherence setting it takes, and
// log+hwq with each query schedule.
std::vector<Setting> gridSettings(Method m) {
  const MethodInfo& info = methodInfo(m);
  std::vector<Setting> out;
  std::vector<std::optional<std::uint32_t>> ks{std::nullopt};
  if (info.takes.lookahead) ks = {1u, 4u, kUnlimitedLookahead};
  for (const std::optional<std::uint32_t>& k : ks) {
    for (bool tc : {false, true}) {
      if (tc && !info.takes.temporal_coherence) continue;
      out.push_back({choice(m, k, tc)});
    }
  }
  if (info.takes.query_schedule) {
    // Each schedule keeps what it learnt of every node from frame to frame.
    out.clear();
    for (QuerySchedule q :
         {QuerySchedule::Hwq, QuerySchedule::Chc, QuerySchedule::Stat, QuerySchedule::Nohc}) {
      samples::MethodChoice c{m};
      c.schedule = q;
      out.push_back({c});
    }
  }
  return out;
}

std::vector<Method> gridMethods() {
  std::vector<Method> out;
  for (const MethodInfo& info : methodTable()) {
    if (info.grid) out.push_back(info.method);
  }
  return out;
}

// A hierarchy over some of the scene's objects, with the scene's object ids.
bvh::FlatHierarchy hierarchyOver(const std::vector<Aabb>& boxes, const std::vector<ObjectId>& ids,
                                 std::uint32_t leaf, std::uint32_t children) {
  std::vector<Aabb> some;
  some.reserve(ids.size());
  for (ObjectId id : ids) some.push_back(boxes[id]);
  bvh::BuildArgs args;
  args.max_leaf_size = leaf;
  args.max_children = children;
  bvh::FlatHierarchy h = bvh::buildOverBoxes(some, args);
  for (ObjectId& o : h.mutableObjects()) o = ids[o];
  return h;
}

std::vector<ObjectId> allObjects(std::size_t n) {
  std::vector<ObjectId> ids(n);
  for (std::size_t i = 0; i < n; ++i) ids[i] = ObjectId(i);
  return ids;
}

// One sequence: renders poses with one runner and checks each frame.
class Sequence {
 public:
  Sequence(const SceneKey& key, LoadedScene& scene, const Setting& setting, Kind kind)
      : key_(key), scene_(scene), kind_(kind) {
    OracleCase c;
    c.scene = key;
    c.method = setting.method;
    c.reader = setting.reader;
    c.frames = kPathFrames;
    config_ = configFor(c, scene.prepared);
    config_.frames = kPathFrames;  // poses, not the intensity
    runner_ = std::make_unique<samples::FrameRunner>(scene.prepared, *scene.renderer, config_);
    label_ = settingName(setting) + " " + toString(kind);
  }

  samples::FrameRunner& runner() { return *runner_; }
  const samples::ViewSettings& view() const { return config_.view; }
  samples::CameraPose pose(std::size_t f) const { return runner_->poseFor(f); }

  // Renders `pose` and checks it; `after` names what changed before this frame.
  samples::FrameRecord frame(const samples::CameraPose& pose, const std::string& after) {
    const std::size_t f = frames_++;
    const samples::FrameRecord r = runner_->renderPose(pose, f);
    const std::string where =
        label_ + " frame " + std::to_string(f) + " (after " + after + "; eye " +
        std::to_string(pose.position.x) + ", " + std::to_string(pose.position.y) + ", " +
        std::to_string(pose.position.z) + "; look at " + std::to_string(pose.look_at.x) + ", " +
        std::to_string(pose.look_at.y) + ", " + std::to_string(pose.look_at.z) + ")";
    EXPECT_GE(r.visible, 0) << "the oracle did not run: " << where;
    EXPECT_EQ(r.missed, 0) << r.missed << " of " << r.visible << " visible objects missed in "
                           << where << [&] {
                                std::string ids;
                                for (ObjectId id : r.missed_ids) ids += " " + std::to_string(id);
                                return "; first missed:" + ids;
                              }();
    EXPECT_EQ(r.missed_artifacts, 0) << where;
    visible_ += std::uint64_t(std::max<std::int64_t>(r.visible, 0));
    occluded_ += r.stats.boxes_occluded;
    coherent_ += r.stats.coherent_leaves;
    last_drawn_ = runner_->drawnObjects();
    return r;
  }

  // A frame right after the hierarchy changed: no leaf of the last frame is drawn first.
  void frameAfterNewHierarchy(const samples::CameraPose& pose, const std::string& after) {
    const samples::FrameRecord r = frame(pose, after);
    EXPECT_EQ(r.stats.coherent_leaves, 0u)
        << label_ << ": after " << after << " the culler drew " << r.stats.coherent_leaves
        << " leaves of the last frame's hierarchy first; it must forget them";
  }

  const std::vector<ObjectId>& lastDrawn() const { return last_drawn_; }

  void summarize() const {
    std::printf("[ oracle ] %s: %zu frames, %llu visible, %llu occluded, %llu coherent leaves\n",
                label_.c_str(), frames_, (unsigned long long)visible_,
                (unsigned long long)occluded_, (unsigned long long)coherent_);
    EXPECT_GT(visible_, 0u) << label_;
    if (config_.culler.temporal_coherence) {
      EXPECT_GT(coherent_, 0u) << label_ << ": no leaf was ever drawn first; coherence untested";
    }
  }
  std::uint64_t occluded() const { return occluded_; }

 private:
  SceneKey key_;
  LoadedScene& scene_;
  Kind kind_;
  samples::RunConfig config_;
  std::unique_ptr<samples::FrameRunner> runner_;
  std::string label_;
  std::size_t frames_ = 0;
  std::uint64_t visible_ = 0, occluded_ = 0, coherent_ = 0;
  std::vector<ObjectId> last_drawn_;
};

void runSequence(Kind kind, Sequence& s, LoadedScene& scene) {
  const std::size_t a = 10;  // where the sequences start on the path
  switch (kind) {
    case Kind::Cut: {
      s.frame(s.pose(a), "nothing");
      s.frame(s.pose(a + 1), "a step along the path");
      // Far along the path, looking back the way the path came.
      samples::CameraPose far = s.pose(32);
      const samples::CameraPose before = s.pose(30);
      far.look_at = before.position;
      s.frame(far, "a cut to an unrelated pose");
      s.frame(s.pose(a + 2), "a cut back");
      s.frame(s.pose(a + 3), "a step along the path");
      break;
    }
    case Kind::Teleport: {
      s.frame(s.pose(a), "nothing");
      const samples::CameraPose q = s.pose(a + 1);
      s.frame(q, "a step along the path");
      // Past the point looked at: behind what the last frame saw in front.
      const glm::dvec3 d = q.look_at - q.position;
      samples::CameraPose behind = q;
      behind.position = q.look_at + d;
      behind.look_at = behind.position + d;
      s.frame(behind, "a teleport behind the last frame's occluders");
      samples::CameraPose back = behind;
      back.look_at = q.position;
      s.frame(back, "turning back to face them");
      s.frame(q, "a teleport back");
      break;
    }
    case Kind::Resize: {
      const samples::ViewSettings base = s.view();
      s.frame(s.pose(a), "nothing");
      std::size_t f = a;
      for (auto [w, h] : {std::pair<std::uint32_t, std::uint32_t>{321, 239},
                          {97, 203},
                          {64, 48},
                          {base.width, base.height}}) {
        samples::ViewSettings v = base;
        v.width = w;
        v.height = h;
        s.runner().setView(v);
        s.frame(s.pose(++f), "resizing to " + std::to_string(w) + "x" + std::to_string(h));
      }
      break;
    }
    case Kind::DepthFormat: {
      const samples::ViewSettings base = s.view();
      s.frame(s.pose(a), "nothing");
      std::size_t f = a;
      const std::pair<DepthConvention, DepthFormat> steps[] = {
          {DepthConvention::Standard, DepthFormat::D24},
          {DepthConvention::Reversed, DepthFormat::D24},
          {DepthConvention::Reversed, DepthFormat::D32F},
          {DepthConvention::Standard, DepthFormat::D32F}};
      for (const auto& [convention, format] : steps) {
        samples::ViewSettings v = base;
        v.depth = samples::depthSetupFor(convention, format);
        s.runner().setView(v);
        s.frame(s.pose(++f), std::string("changing the depth buffer to ") + toString(convention) +
                                 " " + formatName(format));
      }
      break;
    }
    case Kind::Rebuild: {
      const std::vector<Aabb>& boxes = scene.prepared.object_boxes;
      bvh::FlatHierarchy h = hierarchyOver(boxes, allObjects(boxes.size()), 1, 2);
      s.runner().setHierarchy(&h);
      s.frame(s.pose(a), "nothing");
      s.frame(s.pose(a + 1), "a step along the path");
      h = hierarchyOver(boxes, allObjects(boxes.size()), 4, 4);  // same object, other nodes
      s.frameAfterNewHierarchy(s.pose(a + 2), "rebuilding the hierarchy in place");
      s.frame(s.pose(a + 3), "a step along the path");
      h = hierarchyOver(boxes, allObjects(boxes.size()), 2, 8);
      s.frameAfterNewHierarchy(s.pose(a + 3), "rebuilding it again");
      s.runner().setHierarchy(nullptr);
      break;
    }
    case Kind::Replace: {
      const std::vector<Aabb>& boxes = scene.prepared.object_boxes;
      const bvh::FlatHierarchy first = hierarchyOver(boxes, allObjects(boxes.size()), 1, 2);
      const bvh::FlatHierarchy second = hierarchyOver(boxes, allObjects(boxes.size()), 3, 4);
      s.runner().setHierarchy(&first);
      s.frame(s.pose(a), "nothing");
      s.frame(s.pose(a + 1), "a step along the path");
      s.runner().setHierarchy(&second);
      s.frameAfterNewHierarchy(s.pose(a + 2), "replacing the hierarchy");
      s.frame(s.pose(a + 3), "a step along the path");
      s.runner().setHierarchy(&first);
      s.frameAfterNewHierarchy(s.pose(a + 4), "going back to the first hierarchy");
      s.runner().setHierarchy(nullptr);
      break;
    }
    case Kind::RemoveAdd: {
      const std::vector<Aabb>& boxes = scene.prepared.object_boxes;
      const std::vector<ObjectId> all = allObjects(boxes.size());
      const bvh::FlatHierarchy full = hierarchyOver(boxes, all, 1, 2);
      s.runner().setHierarchy(&full);
      s.frame(s.pose(a), "nothing");
      s.frame(s.pose(a + 1), "a step along the path");
      // Without what the last frame drew: what it hid shows now.
      std::vector<ObjectId> drawn = s.lastDrawn();
      std::sort(drawn.begin(), drawn.end());
      std::vector<ObjectId> rest;
      std::set_difference(all.begin(), all.end(), drawn.begin(), drawn.end(),
                          std::back_inserter(rest));
      ASSERT_FALSE(drawn.empty());
      ASSERT_FALSE(rest.empty());
      const bvh::FlatHierarchy removed = hierarchyOver(boxes, rest, 1, 2);
      s.runner().setHierarchy(&removed);
      s.frameAfterNewHierarchy(s.pose(a + 1), "removing the " + std::to_string(drawn.size()) +
                                                  " objects the last frame drew");
      s.frame(s.pose(a + 2), "a step along the path");
      const bvh::FlatHierarchy again = hierarchyOver(boxes, all, 1, 2);
      s.runner().setHierarchy(&again);
      s.frameAfterNewHierarchy(s.pose(a + 3), "adding them back");
      s.frame(s.pose(a + 4), "a step along the path");
      s.runner().setHierarchy(nullptr);
      break;
    }
  }
}

struct DiscontinuityCase {
  Kind kind;
  Method method;
};

class Discontinuity : public testing::TestWithParam<DiscontinuityCase> {};

TEST_P(Discontinuity, NoVisibleObjectIsMissedAndStaleNodesAreForgotten) {
  LOGRID_REQUIRE_GL();
  const DiscontinuityCase& c = GetParam();
  const SceneKey key = cityKey();
  LoadedScene& scene = loadScene(key);
  std::vector<Setting> settings = gridSettings(c.method);
  // The CPU occlusion buffer and the asynchronous reader across the view's changes.
  if (c.method == Method::LogZfar && (c.kind == Kind::Resize || c.kind == Kind::DepthFormat)) {
    settings.push_back({choice(Method::LogZfar, 4u, true), "cpu"});
    settings.push_back({choice(Method::LogZfar, kUnlimitedLookahead, true), "pbo"});
  }
  std::uint64_t occluded = 0;
  for (const Setting& setting : settings) {
    Sequence s(key, scene, setting, c.kind);
    runSequence(c.kind, s, scene);
    s.summarize();
    occluded += s.occluded();
  }
  EXPECT_GT(occluded, 0u) << "no box was ever found occluded; the sequences test nothing";
}

std::vector<DiscontinuityCase> discontinuityCases() {
  std::vector<DiscontinuityCase> out;
  for (Kind k : {Kind::Cut, Kind::Teleport, Kind::Resize, Kind::DepthFormat, Kind::Rebuild,
                 Kind::Replace, Kind::RemoveAdd}) {
    for (Method m : gridMethods()) {
      // ddo+log's occluders stand for the scene's geometry as its octree was built: an
      // application that removes objects builds its octree again (not done here).
      if (k == Kind::RemoveAdd && methodInfo(m).needs.occluders) continue;
      out.push_back({k, m});
    }
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Grid, Discontinuity, testing::ValuesIn(discontinuityCases()),
                         [](const testing::TestParamInfo<DiscontinuityCase>& p) {
                           return sanitize(std::string(toString(p.param.kind)) + "_" +
                                           logrid::toString(p.param.method));
                         });

}  // namespace
}  // namespace logrid::oracle
