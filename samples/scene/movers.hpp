// Moving objects for the sample scenes (`--movers N`): animals in the forest, vehicles
// in the city, deterministic from the seed. Each is a mesh of a few hundred to a few
// thousand triangles (movers of one shape share the geometry) moving along a path of
// its own scene (motion.hpp):
//   * animals walk loops through the trees at 0.5-3 m/s; a tenth of the paths are long
//     straight tracks that reach 25 % beyond the scene on both sides (movers leave the
//     scene bounds and come back);
//   * vehicles drive at 3-12 m/s around blocks and along whole streets, which also
//     reach beyond the city on both sides;
//   * about three movers share each path, in both directions, in one lane: they pass
//     through each other;
//   * half of them stop and start again (moving 10-60 s, standing 5-40 s).
// A scene from a file gets animals on the floor of its bounds, sized to the scene; its
// own meshes can move along paths with --animate (motion.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "scene/scene.hpp"

namespace logrid::samples {

// Adds `count` movers to `scene` (appended to Scene::moving and Scene::motion) for its
// mover site, deterministic from `seed`. Throws logrid::Error(InvalidArgument) for a
// count over kMaxMovers.
inline constexpr std::uint32_t kMaxMovers = 1'000'000;
void addMovers(Scene& scene, std::uint32_t count, std::uint64_t seed);

// Moves the listed meshes of a scene from a file into Scene::moving, animated along
// their paths (loadMeshAnimations, motion.hpp; paths in world coordinates).
void animateMeshes(Scene& scene, const std::string& motion_file);

}  // namespace logrid::samples
