// The forest split into parts (--tree-parts): every way of splitting a tree gives a valid
// scene with one occluder-model slot per object and each tree's model once.
#include <gtest/gtest.h>

#include "scene/generators.hpp"
#include "scene/scene.hpp"

namespace logrid::samples {
namespace {

std::size_t modelsWithTriangles(const Scene& scene) {
  std::size_t n = 0;
  for (const OccluderModel& m : scene.occluder_models) n += !m.indices.empty();
  return n;
}

TEST(ForestParts, EverySplitIsAValidSceneWithEachTreesModelOnce) {
  const Scene whole = makeForest({0.05, 1, TreeParts::Whole});
  ASSERT_NO_THROW(validateScene(whole));
  for (TreeParts parts : {TreeParts::TrunkCrown, TreeParts::Tiers}) {
    const Scene split = makeForest({0.05, 1, parts});
    EXPECT_NO_THROW(validateScene(split)) << toString(parts);
    EXPECT_GT(split.objects.size(), whole.objects.size()) << toString(parts);
    EXPECT_EQ(split.occluder_models.size(), split.objects.size()) << toString(parts);
    EXPECT_EQ(modelsWithTriangles(split), modelsWithTriangles(whole)) << toString(parts);
  }
}

}  // namespace
}  // namespace logrid::samples
