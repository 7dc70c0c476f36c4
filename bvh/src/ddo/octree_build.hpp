// The octree's subdivision (DDO §3.1, figure 5 without the masks). Internal.
#pragma once

#include "logrid/ddo/build.hpp"
#include "logrid/ddo/octree.hpp"

namespace logrid::ddo::detail {

// Subdivides a cube around the mesh's bounds while a node holds more than
// args.leaf_triangles triangles (by centroid) and is above args.max_depth; fills the
// tight bounds and the leaves' object lists. The masks are left at zero.
Octree subdivide(const SceneMesh& mesh, const BuildArgs& args);

}  // namespace logrid::ddo::detail
