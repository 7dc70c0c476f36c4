// Procedural scenes at the scale of LOG §5, deterministic from a seed.
//
//   forest  terrain patches and trees (trunk and crown), each tree and each patch one
//           object; about 1.7 million triangles at scale 1 (the paper: 1,694,426). The
//           walkthrough follows a trail through the trees at eye height.
//   city    a street grid of buildings of varied height with window bays; the hierarchy
//           is built over triangles (chunks of at most 1500); about 34 million
//           triangles at scale 1 (the paper: 34,034,176). The walkthrough follows the
//           streets at street level.
// `scale` multiplies the number of trees or buildings (and the area, so density and
// depth complexity stay the same); the camera path stays inside the scene.
#pragma once

#include <cstdint>

#include "scene/scene.hpp"

namespace logrid::samples {

// How the forest's trees become objects, each with its own box: box granularity
// decides how much of a tree's box peeks out where its geometry does not.
enum class TreeParts : std::uint8_t {
  Whole,       // one object per tree (LOG §5: "each tree is an object")
  TrunkCrown,  // the trunk and the crown apart
  Tiers,       // the trunk and each tier of a conifer's crown apart
};
const char* toString(TreeParts parts);

struct GeneratorOptions {
  double scale = 1.0;  // > 0; 0.01 gives a quick test scene
  std::uint64_t seed = 1;
  TreeParts tree_parts = TreeParts::Whole;  // forest only
};

// The largest scale of each scene: larger ones would not fit in 32-bit indices (or, for
// the city, in memory: scale 16 is about 540 million triangles).
inline constexpr double kMaxForestScale = 1000;
inline constexpr double kMaxCityScale = 16;
inline constexpr double kMaxOfficeScale = 64;

// Throws logrid::Error(InvalidArgument) naming the scene for a scale outside (0, max]
// (NaN included); `note` follows the range in the message.
void checkScale(const char* scene, double scale, double max, const char* note = "");

// Throw logrid::Error(InvalidArgument) for a scale that is not finite and positive, or
// above the scene's largest (kMax*Scale).
Scene makeForest(const GeneratorOptions& options);
Scene makeCity(const GeneratorOptions& options);
// An office building (indoor, finely tessellated closed boxes everywhere; see office.cpp):
// 12 rooms on each side of three corridors at scale 1.
Scene makeOffice(const GeneratorOptions& options);

}  // namespace logrid::samples
