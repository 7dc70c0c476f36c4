#include "logrid/bvh/motion.hpp"

#include <cassert>
#include <chrono>
#include <cmath>
#include <sstream>
#include <utility>

#include "logrid/bvh/ternary_tree.hpp"
#include "logrid/elapsed.hpp"
#include "logrid/error.hpp"

namespace logrid::bvh {
namespace {

Status checkUpdate(const char* who, const MotionUpdate& u, std::size_t objects) {
  if (!u.boxes || !u.moved) {
    return Status(ErrorCode::InvalidArgument, std::string(who) + ": boxes and moved must be given");
  }
  if (u.boxes->size() < objects) {
    std::ostringstream out;
    out << who << ": " << u.boxes->size() << " boxes given for " << objects << " objects";
    return Status(ErrorCode::InvalidArgument, out.str());
  }
  for (ObjectId id : *u.moved) {
    if (id >= objects) {
      std::ostringstream out;
      out << who << ": moved object " << id << " is out of range (" << objects << " objects)";
      return Status(ErrorCode::InvalidArgument, out.str());
    }
  }
  return {};
}

// A FlatHierarchy shown through MotionHierarchy: `flat` built over `objects` boxes.
class FlatMotion : public MotionHierarchy {
 public:
  FlatMotion(FlatHierarchy flat, std::size_t objects, const BuildArgs& args)
      : args_(args), flat_(std::move(flat)), objects_(objects) {}

  NodeId root() const override { return flat_.root(); }
  Aabb bounds(NodeId node) const override { return flat_.bounds(node); }
  std::uint32_t childCount(NodeId node) const override { return flat_.childCount(node); }
  NodeId child(NodeId node, std::uint32_t i) const override { return flat_.child(node, i); }
  std::uint32_t objectCount(NodeId node) const override { return flat_.objectCount(node); }
  ObjectId object(NodeId node, std::uint32_t i) const override { return flat_.object(node, i); }
  std::uint64_t revision() const override { return flat_.revision(); }
  std::size_t objectTotal() const override { return objects_; }
  const FlatHierarchy& flat() const { return flat_; }

 protected:
  BuildArgs args_;
  FlatHierarchy flat_;
  std::size_t objects_;
};

// Refit the moved objects' paths; rebuild when the surface-area sum has grown too much.
class RefitMotion final : public FlatMotion {
 public:
  RefitMotion(FlatHierarchy flat, std::size_t objects, const BuildArgs& args, double growth)
      : FlatMotion(std::move(flat), objects, args),
        growth_(growth),
        built_area_(flat_.surfaceAreaSum()) {}

  Result<UpdateStats> tryUpdate(const MotionUpdate& u) override {
    const auto start = std::chrono::steady_clock::now();
    if (Status s = checkUpdate("refit", u, objects_); !s) return s;
    UpdateStats stats;
    stats.moved = static_cast<std::uint32_t>(u.moved->size());
    if (Status s = flat_.tryRefit(*u.boxes, *u.moved).status(); !s) return s;
    const double area = flat_.surfaceAreaSum();
    stats.quality = built_area_ > 0 ? area / built_area_ : 1.0;
    if (stats.quality > 1.0 + growth_) {
      std::vector<Aabb> boxes(u.boxes->begin(), u.boxes->begin() + std::ptrdiff_t(objects_));
      Result<FlatHierarchy> rebuilt = tryBuildOverBoxes(boxes, args_);
      if (!rebuilt) return rebuilt.status();
      flat_ = std::move(rebuilt).value();
      built_area_ = flat_.surfaceAreaSum();
      stats.rebuilds = 1;
    }
    stats.seconds = secondsSince(start);
    return stats;
  }

 private:
  double growth_;
  double built_area_;
};

class RebuildMotion final : public FlatMotion {
 public:
  using FlatMotion::FlatMotion;

  Result<UpdateStats> tryUpdate(const MotionUpdate& u) override {
    const auto start = std::chrono::steady_clock::now();
    if (Status s = checkUpdate("rebuild", u, objects_); !s) return s;
    UpdateStats stats;
    stats.moved = static_cast<std::uint32_t>(u.moved->size());
    Result<FlatHierarchy> rebuilt =
        u.boxes->size() == objects_
            ? tryBuildOverBoxes(*u.boxes, args_)
            : tryBuildOverBoxes({u.boxes->begin(), u.boxes->begin() + std::ptrdiff_t(objects_)},
                                args_);
    if (!rebuilt) return rebuilt.status();
    flat_ = std::move(rebuilt).value();
    stats.rebuilds = 1;
    stats.seconds = secondsSince(start);
    return stats;
  }
};

}  // namespace

const std::vector<MotionInfo>& motionTable() {
  static const std::vector<MotionInfo> table = {
      {MotionKind::Refit, "refit",
       "BVH refitted where objects moved, rebuilt when its surface-area sum has grown"},
      {MotionKind::Rebuild, "rebuild", "BVH rebuilt from every object's box each frame"},
      {MotionKind::Ternary, "ternary",
       "ternary tree with tight boxes and split/merge from pixel statistics (Kovalcik)"},
      {MotionKind::TernaryObjects, "ternary-objects",
       "the ternary tree with every object tested on its own box (not in the paper)"},
      {MotionKind::Binary, "binary",
       "the paper's old algorithm: BSP tree, straddling objects in the inner node"},
  };
  return table;
}

const MotionInfo& motionInfo(MotionKind kind) {
  const auto& table = motionTable();
  assert(std::size_t(kind) < table.size() && "motionInfo: unknown kind");
  return table[std::size_t(kind)];
}

std::optional<MotionKind> parseMotionKind(const std::string& name) {
  for (const MotionInfo& m : motionTable()) {
    if (name == m.name) return m.kind;
  }
  return std::nullopt;
}

std::string motionNames() {
  std::string out;
  for (const MotionInfo& m : motionTable()) {
    if (!out.empty()) out += ", ";
    out += m.name;
  }
  return out;
}

TernaryDesc binaryTreeDesc(const TernaryDesc& base) {
  TernaryDesc d = base;
  d.third_child = false;
  d.tight_boxes = false;
  d.split_merge = false;
  return d;
}

std::string validateMotionDesc(const MotionDesc& desc) {
  std::ostringstream out;
  const std::string build = validateBuildArgs(desc.build);
  const TernaryDesc& t = desc.ternary;
  if (!build.empty()) {
    out << "motion: " << build;
  } else if (!(desc.rebuild_growth >= 0) || !std::isfinite(desc.rebuild_growth)) {
    out << "motion: rebuild_growth " << desc.rebuild_growth
        << " is invalid; use a finite fraction >= 0 (0.25: rebuild once the surface-area sum "
           "grew by 25%)";
  } else if (!(t.r_split >= 0 && t.r_split <= 1) || !(t.r_merge >= 0 && t.r_merge <= 1)) {
    out << "ternary tree: r_split " << t.r_split << " and r_merge " << t.r_merge
        << " must be pixel ratios in [0, 1]";
  } else if (t.o_split < 2) {
    out << "ternary tree: o_split " << t.o_split << " is invalid; use 2 objects or more";
  } else if (t.max_depth < 1 || t.max_depth > 64) {
    out << "ternary tree: max_depth " << t.max_depth << " is out of range; use 1 to 64";
  } else if (t.still_frames > 1000) {
    out << "ternary tree: still_frames " << t.still_frames << " is out of range; use 0 to 1000";
  } else if (t.build_leaf == 1) {
    out << "ternary tree: build_leaf 1 is invalid; use 0 (o_split) or 2 objects or more";
  }
  return out.str();
}

namespace {

using Made = Result<std::unique_ptr<MotionHierarchy>>;

Made makeFlat(MotionKind kind, const std::vector<Aabb>& boxes, const MotionDesc& desc) {
  Result<FlatHierarchy> flat = tryBuildOverBoxes(boxes, desc.build);
  if (!flat) return flat.status();
  if (kind == MotionKind::Refit) {
    return Made(std::make_unique<RefitMotion>(std::move(flat).value(), boxes.size(), desc.build,
                                              desc.rebuild_growth));
  }
  return Made(std::make_unique<RebuildMotion>(std::move(flat).value(), boxes.size(), desc.build));
}

Made makeTernary(const std::vector<Aabb>& boxes, const TernaryDesc& desc) {
  Result<TernaryTree> tree = TernaryTree::create(boxes, desc);
  if (!tree) return tree.status();
  return Made(std::make_unique<TernaryTree>(std::move(tree).value()));
}

}  // namespace

Result<std::unique_ptr<MotionHierarchy>> tryMakeMotionHierarchy(MotionKind kind,
                                                                const std::vector<Aabb>& boxes,
                                                                const MotionDesc& desc) {
  std::string problem = validateMotionDesc(desc);
  if (!problem.empty()) return Status(ErrorCode::InvalidArgument, std::move(problem));
  switch (kind) {
    case MotionKind::Refit:
    case MotionKind::Rebuild: return makeFlat(kind, boxes, desc);
    case MotionKind::Ternary: return makeTernary(boxes, desc.ternary);
    case MotionKind::TernaryObjects: {
      TernaryDesc d = desc.ternary;
      d.object_nodes = true;
      return makeTernary(boxes, d);
    }
    case MotionKind::Binary: return makeTernary(boxes, binaryTreeDesc(desc.ternary));
  }
  return Status(ErrorCode::InvalidArgument, "motion: unknown hierarchy kind");
}

}  // namespace logrid::bvh
