// The city-like hierarchy and street camera that the traversal and projection
// benchmarks share (docs/MICROBENCH.md).
#pragma once

#include "logrid/bvh/bvh.hpp"
#include "logrid/camera.hpp"

namespace logrid {

// The street grid of the city scene (samples/scene/city.cpp: 76 m blocks, 24 m streets,
// 1190 blocks) with four buildings a block, 4 to 20 storeys of 3.5 m, each wall one
// object (the city's hierarchy is built over chunks of its facade triangles: thin boxes
// along the walls, about 23,000 of them at scale 1): 19,040 walls, built once.
const bvh::FlatHierarchy& cityHierarchy();

// 640 x 480, at eye height in a street at one end of the city, looking along it; the
// render origin is the eye.
Camera cityCamera(const DepthSetup& depth);

}  // namespace logrid
