// Internal to logrid::cpu: from an object's welded mesh to the triangles the raster
// kernels read (raster/raster_triangle.hpp), following the rules documented in
// logrid/cpu/occlusion_buffer.hpp. Double precision throughout; floats only at the end.
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/cpu/occluder_mesh.hpp"
#include "raster/raster_triangle.hpp"

namespace logrid::cpu::detail {

// What every object of a frame shares.
struct SetupFrame {
  double m[16] = {};  // view_projection: local coordinates to clip space
  double half_w = 0, half_h = 0;
  double key_scale = 0, key_offset = 0;  // key = (key_scale z + key_offset w) / w
  double near_key = 0, clear_key = 1;
  int scale = 1;      // viewport pixels per buffer pixel
  double radius = 0;  // half the spread of a buffer pixel's samples: (scale - 1) / 2
  std::int32_t buffer_w = 0, buffer_h = 0;
  bool exact_coverage = false;  // test aids (OcclusionBufferDesc::unsafe_*)
  bool exact_depth = false;
};

// One object to set up.
struct SetupObject {
  std::uint32_t occluder = 0;  // index into the meshes
  double s_x = 0, s_y = 0;     // how far GL may move a vertex, per axis (viewport pixels)
  double margin = 0;           // depth margin of the object's box (projection.hpp)
};

class TriangleSetup {
 public:
  // Appends the object's usable triangles to `out` (neighbours refer to indices in
  // `out`) and returns how many triangles of the object it looked at.
  std::size_t run(const SetupFrame& frame, const OccluderMeshes& meshes, const SetupObject& object,
                  std::vector<RasterTriangle>& out);

 private:
  struct Vertex {
    double x, y, w, k;  // homogeneous window x, y, clip w, homogeneous key
  };
  struct Work {
    double a[kTriangleEdges], b[kTriangleEdges], c[kTriangleEdges];
    double slack[kTriangleEdges], err[kTriangleEdges];
    double za, zb, zc;  // key plane at the reference
    double s_x, s_y;    // per-triangle displacement bound
    double rx, ry;
    std::int32_t x0, y0, x1, y1;
    bool clipped;
    std::uint32_t out;  // index in the output, kNoNeighbour when unusable
  };
  bool setUp(const SetupFrame& frame, const SetupObject& object, const std::uint32_t* corners,
             std::uint32_t first_vertex, Work& work) const;

  std::vector<Vertex> vertices_;
  std::vector<Work> work_;
};

}  // namespace logrid::cpu::detail
