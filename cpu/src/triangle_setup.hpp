// Internal to logrid::cpu: from an object's welded mesh to the triangles the raster
// kernels read (raster/raster_triangle.hpp), following the rules documented in
// logrid/cpu/occlusion_buffer.hpp. Double precision throughout; floats only at the end.
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/cpu/occluder_mesh.hpp"
#include "raster/raster_triangle.hpp"

namespace logrid::cpu::detail {

inline constexpr double kU = 1.0 / 16777216.0;  // float unit roundoff, 2^-24
// Window coordinates beyond this many pixels are too coarse in float for the kernels.
inline constexpr double kGuardBand = 4194304.0;  // 2^22

// What every object of a frame shares.
struct SetupFrame {
  double m[16] = {};  // view_projection: local coordinates to clip space
  // GL's float error model (projection.hpp): the renderer transforms q = p - origin with
  // the matrix `render` = view_projection * translation(origin); |render| bounds the
  // magnitudes of the terms it sums.
  double render_abs[16] = {};
  double clip_abs[4] = {};  // sum_j |m[r + 4 j]| over j < 3: clip r per unit of world motion
  double origin[3] = {};
  double render_k = 0;      // kRenderErrorUlps * u, as configured
  double quantisation = 0;  // one step of the depth format, as configured
  double snap = 0;          // how far snapping may move a vertex, per axis (pixels)
  double half_w = 0, half_h = 0;
  double key_scale = 0, key_offset = 0;  // key = (key_scale z + key_offset w) / w
  double near_key = 0, clear_key = 1;
  int scale = 1;  // viewport pixels per buffer pixel
  double inv_scale = 1;
  double radius = 0;  // half the spread of a buffer pixel's samples: (scale - 1) / 2, + 0.5
                      // for a multisampled camera
  std::int32_t buffer_w = 0, buffer_h = 0;
  bool skip_closed_back_faces = true;
  bool exact_coverage = false;  // test aids (OcclusionBufferDesc::unsafe_*)
  bool exact_depth = false;
};

// One object to set up. Each triangle's bounds come from its own vertices; these are
// floors under them (for a model inside an object: the object box's, since GL draws the
// object's vertices, not the model's).
struct SetupObject {
  std::uint32_t occluder = 0;  // index into the meshes
  double s_x = 0, s_y = 0;     // how far GL may move a vertex, per axis (viewport pixels)
  double margin = 0;           // depth margin (projection.hpp)
  // A moving object (occlusion_buffer.hpp, "Moving objects"): its vertices placed at
  // rotation * p + translation, GL's within `pad` of them per axis (world units);
  // `orientation` the sign of the rotation's determinant (0: singular).
  bool moved = false;
  double rotation[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double translation[3] = {0, 0, 0};
  double pad = 0;
  int orientation = 1;
};

class TriangleSetup {
 public:
  // Transform a still object's vertices and set up the triangles wholly in front of the
  // near plane four at a time (AVX2, where the CPU has it: triangle_setup_avx2.cpp), bit
  // for bit as transform() and setUp() do one at a time; the rest one at a time. Off by
  // default. Returns whether it is on.
  bool useGroups(bool on);

  // Writes the object's usable triangles to out[count, ...) (neighbours refer to indices
  // in `out`), growing `out` where needed but never clearing it (a frame reuses it),
  // advances `count`, and returns how many triangles of the object it looked at.
  std::size_t run(const SetupFrame& frame, const OccluderMeshes& meshes, const SetupObject& object,
                  std::vector<RasterTriangle>& out, std::size_t& count);

 private:
  struct Vertex {
    double x, y, w, k;      // homogeneous window x, y, clip w, homogeneous key
    double sx, sy, sz, sw;  // magnitudes of the terms of GL's clip x, y, z, w
    bool front;             // w > 0 and not beyond the near plane
    bool beyond_far;
    double wx, wy, key;  // window position and key (where front)
    double ex, ey, ez;   // GL's float error there, before the ulps factor
    double px, py, pz;   // a moving object's pad there (window x, y, key; 0 if still)
  };
  struct Work {
    double a[kTriangleEdges], b[kTriangleEdges], c[kTriangleEdges];
    double slack[kTriangleEdges], err[kTriangleEdges];
    double za, zb, zc;  // key plane (at the reference once finished)
    double s_x, s_y;    // how far GL may move the vertices, per axis
    double margin;      // depth margin
    double key_min;     // the nearest key of its (clipped) vertices
    double g;           // |dz/dx| + |dz/dy| of the key plane
    double z_err;       // float error of the kernels' evaluation of the plane
    double rx, ry;
    std::int32_t x0, y0, x1, y1;
    bool clipped;
    std::uint32_t out;  // index in the output, kNoNeighbour when unusable
  };
  void transform(const SetupFrame& frame, const SetupObject& object, const float* positions,
                 std::uint32_t count);
  bool setUp(const SetupFrame& frame, const SetupObject& object, const std::uint32_t* corners,
             std::uint32_t first_vertex, std::uint8_t closed, Work& work) const;
  bool setUpClipped(const SetupFrame& frame, const SetupObject& object, const Vertex* const* v,
                    Work& work) const;
  bool pixelBounds(const SetupFrame& frame, double x_min, double x_max, double y_min, double y_max,
                   Work& work) const;
  void finish(const SetupFrame& frame, Work& work) const;
  // Twice the signed area of a triangle in window space.
  static double windowArea(const Vertex* const* v) {
    return (v[1]->wx - v[0]->wx) * (v[2]->wy - v[0]->wy) -
           (v[2]->wx - v[0]->wx) * (v[1]->wy - v[0]->wy);
  }
  // A closed surface's triangles that face the eye (counter-clockwise for a surface wound
  // so from outside) cover all it covers: the others are left out.
  static bool facingAway(const SetupFrame& frame, double area, std::uint8_t closed) {
    return closed != 0 && frame.skip_closed_back_faces && (area < 0) == (closed == 1);
  }
  // setUp() of four triangles wholly in front of the near plane and not facing away
  // (corners[3 l + k]: corner k of lane l), writing work[l] and ok[l] as setUp() writes
  // them and returns, bit for bit.
  // transform() of a still object's vertices [0, 4 floor(count / 4)) into out, as it
  // writes them wherever they are in front of the near plane (and the flags everywhere);
  // returns how many it did.
  static std::uint32_t transformGroupsAvx2(const SetupFrame& frame, const float* positions,
                                           std::uint32_t count, Vertex* out);
  static void setUpGroupAvx2(const SetupFrame& frame, const SetupObject& object,
                             const Vertex* const* corners, Work* const* work, bool* ok);

  // The object's pad in clip coordinates (x, y, z, w): pad * SetupFrame::clip_abs.
  double pad_clip_[4] = {};
  std::vector<Vertex> vertices_;
  std::vector<Work> work_;
  bool groups_ = false;
  Work spare_;  // the unused lanes of a group
};

}  // namespace logrid::cpu::detail
