#include "logrid/ddo/selector.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>

#include "logrid/elapsed.hpp"
#include "logrid/error.hpp"

namespace logrid::ddo {
namespace {

// §4.1's look-up table: child octants front to back are eye_octant ^ kOrder[i].
constexpr int kOrder[8] = {0, 1, 2, 4, 3, 5, 6, 7};

double det3(const double m[3][3]) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

double pointSegmentDistance(const double* p, const double* a, const double* b) {
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  const double ex = a[0] + t * dx - p[0], ey = a[1] + t * dy - p[1];
  return std::sqrt(ex * ex + ey * ey);
}

double pointQuadBoundaryDistance(const double* p, const double q[4][2]) {
  double d = HUGE_VAL;
  for (int i = 0; i < 4; ++i) d = std::min(d, pointSegmentDistance(p, q[i], q[(i + 1) % 4]));
  return d;
}

// Moves every edge of the convex quad q inward by d; false if it collapses.
bool shrinkQuad(const double q[4][2], double d, double out[4][2]) {
  double area = 0;
  for (int i = 0; i < 4; ++i) area += q[i][0] * q[(i + 1) % 4][1] - q[(i + 1) % 4][0] * q[i][1];
  if (!(std::fabs(area) > 0)) return false;
  const double orient = area > 0 ? 1.0 : -1.0;
  // Edge i from q[i] to q[i+1]: inward normal n, line n . x = c.
  double n[4][2], c[4];
  for (int i = 0; i < 4; ++i) {
    const double ex = q[(i + 1) % 4][0] - q[i][0], ey = q[(i + 1) % 4][1] - q[i][1];
    const double len = std::sqrt(ex * ex + ey * ey);
    if (!(len > 0)) return false;
    n[i][0] = -ey / len * orient;
    n[i][1] = ex / len * orient;
    c[i] = n[i][0] * q[i][0] + n[i][1] * q[i][1] + d;
  }
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 3) % 4;  // the edge before vertex i
    const double det = n[j][0] * n[i][1] - n[j][1] * n[i][0];
    if (std::fabs(det) < 1e-12) return false;
    out[i][0] = (c[j] * n[i][1] - n[j][1] * c[i]) / det;
    out[i][1] = (n[j][0] * c[i] - c[j] * n[i][0]) / det;
  }
  double shrunk = 0;
  for (int i = 0; i < 4; ++i) {
    shrunk += out[i][0] * out[(i + 1) % 4][1] - out[(i + 1) % 4][0] * out[i][1];
  }
  if (!(shrunk * orient > 0)) return false;
  // Every new vertex must lie inside the original quad by d (no edge overtook another).
  for (int i = 0; i < 4; ++i) {
    for (int k = 0; k < 4; ++k) {
      if (n[k][0] * out[i][0] + n[k][1] * out[i][1] < c[k] - 1e-9) return false;
    }
  }
  return true;
}

}  // namespace

// A face's outline on screen: its corners' window positions and keys, and the corners
// of the enlarged face.
struct Selector::FaceOutline {
  double win[4][2];
  double key[4];
  double win_plus[4][2];
};

// A selected face, kept for merging.
struct Selector::Face {
  int face = 0;
  int axis = 0, t1 = 1, t2 = 2;
  double plane = 0;
  double lo1 = 0, hi1 = 0, lo2 = 0, hi2 = 0;
  double delta = 0;     // depth push-back, in keys
  bool safe = false;    // the band was wide enough: may be merged, never shrunk
  double window[4][2];  // the outline drawn (shrunk when not safe)
  double plane_key[3];  // key = a + b x + c y over window coordinates, pushed back
};

struct Selector::Frame {
  Camera camera;
  Projector projector;
  const std::function<void(ObjectId)>* draw = nullptr;
  SelectionStats* stats = nullptr;
  bool faces_only = false;  // neither a map nor a draw callback: nodes matter by their faces
  bool ortho = false;
  double eye[3] = {0, 0, 0};  // perspective eye, local coordinates
  double dir[3] = {0, 0, 0};  // orthographic: towards the viewer
  float clear_key = 1;
  double snap_pixels = 0;  // SelectorSettings::snap_pixels
  double key_sign = 1, depth_scale = 0.5, depth_offset = 0.5;
  std::vector<Face> faces;

  double near_plane[4] = {0, 0, 1, 1};  // clip-space half-space in front of the near plane

  ProjectionSettings settings;

  Frame(const Camera& c, Projector p, const ProjectionSettings& s)
      : camera(c), projector(std::move(p)), settings(s) {}

  bool inFrontOfNear(const double* p) const {
    const double* m = camera.view_projection.m;
    double clip[4];
    for (int r = 0; r < 4; ++r)
      clip[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
    const double d = near_plane[0] * clip[0] + near_plane[1] * clip[1] + near_plane[2] * clip[2] +
                     near_plane[3] * clip[3];
    return clip[3] > 0 && d > 1e-9 * (std::fabs(clip[2]) + std::fabs(clip[3]));
  }

  // Local point to window coordinates and key; false if not in front of the eye.
  bool toWindow(const double* p, double* win, double& key) const {
    const double* m = camera.view_projection.m;
    double clip[4];
    for (int r = 0; r < 4; ++r)
      clip[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
    if (!(clip[3] > 0)) return false;
    win[0] = (clip[0] / clip[3] * 0.5 + 0.5) * camera.width;
    win[1] = (clip[1] / clip[3] * 0.5 + 0.5) * camera.height;
    key = key_sign * (depth_scale * clip[2] / clip[3] + depth_offset);
    return true;
  }
};

std::optional<Occluder> makeOccluder(const double window[4][2], const double plane[3],
                                     std::uint32_t faces, const Camera& camera,
                                     const ProjectionSettings& projection) {
  Occluder o;
  const bool zero_to_one = camera.depth.clip_range == ClipDepthRange::ZeroToOne;
  const double key_sign = camera.depth.convention == DepthConvention::Reversed ? -1.0 : 1.0;
  const double depth_scale = zero_to_one ? 1.0 : 0.5, depth_offset = zero_to_one ? 0.0 : 0.5;
  const float clear_key = clearKey(camera.depth);
  double xlo = HUGE_VAL, xhi = -HUGE_VAL, ylo = HUGE_VAL, yhi = -HUGE_VAL;
  double klo = HUGE_VAL, khi = -HUGE_VAL;
  for (int i = 0; i < 4; ++i) {
    const double k = plane[0] + plane[1] * window[i][0] + plane[2] * window[i][1];
    o.ndc[i][0] = window[i][0] / camera.width * 2.0 - 1.0;
    o.ndc[i][1] = window[i][1] / camera.height * 2.0 - 1.0;
    o.ndc[i][2] = (key_sign * k - depth_offset) / depth_scale;
    o.window[i][0] = window[i][0], o.window[i][1] = window[i][1];
    xlo = std::min(xlo, window[i][0]), xhi = std::max(xhi, window[i][0]);
    ylo = std::min(ylo, window[i][1]), yhi = std::max(yhi, window[i][1]);
    klo = std::min(klo, k), khi = std::max(khi, k);
  }
  // One pixel of slack around the outline for the rasteriser's snapping.
  const auto clampX = [&](double v) {
    return std::int32_t(std::clamp(v, 0.0, double(camera.width)));
  };
  const auto clampY = [&](double v) {
    return std::int32_t(std::clamp(v, 0.0, double(camera.height)));
  };
  o.rect = {clampX(std::floor(xlo) - 1), clampY(std::floor(ylo) - 1), clampX(std::ceil(xhi) + 1),
            clampY(std::ceil(yhi) + 1)};
  if (o.rect.empty() || !(klo <= khi)) return std::nullopt;
  // The keys GL stores for the quad: its corner keys, moved by the rounding of drawing
  // it (projection.hpp: the float NDC corners, the viewport transform, interpolation,
  // the conversion and one quantisation step of the depth format), so that a culler
  // told "drawn, no farther than far_key" can rely on it.
  const double margin = projection.quantisation_scale * quantisationStep(camera.depth.format) +
                        projection.render_error_ulps * kUnitRoundoff * (1.0 + std::max(-klo, khi));
  float lo = float(klo - margin);
  if (double(lo) > klo - margin) lo = std::nextafter(lo, -HUGE_VALF);
  float hi = float(khi + margin);
  if (double(hi) < khi + margin) hi = std::nextafter(hi, HUGE_VALF);
  o.near_key = lo;
  o.far_key = std::min(hi, clear_key);
  o.faces = faces;
  return o;
}

Selector::Selector(const Octree& octree, const SelectorSettings& settings)
    : octree_(octree), settings_(settings) {
  ObjectId largest = 0;
  for (ObjectId id : octree.objects()) largest = std::max(largest, id);
  object_stamp_.assign(octree.objects().empty() ? 0 : std::size_t(largest) + 1, 0);
  // Every node after its parent (breadth first from the root); then children before parents.
  with_faces_.assign(octree.nodes().size(), 0);
  if (octree.empty()) return;
  std::vector<std::uint32_t> order{0};
  for (std::size_t i = 0; i < order.size(); ++i) {
    for (int k = 0; k < 8; ++k) {
      const std::uint32_t child = octree.child(order[i], k);
      if (child != Octree::kNone) order.push_back(child);
    }
  }
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    std::uint8_t any = 0;
    for (int f = 0; f < kFaces && !any; ++f) any = octree.mask(*it, f) != 0;
    for (int k = 0; k < 8 && !any; ++k) {
      const std::uint32_t child = octree.child(*it, k);
      if (child != Octree::kNone) any = with_faces_[child];
    }
    with_faces_[*it] = any;
  }
}

Status Selector::trySelect(const Camera& camera, const std::function<void(ObjectId)>& draw,
                           SelectionStats& stats, const ProjectionSettings& projection) {
  const auto start = std::chrono::steady_clock::now();
  stats = {};
  Result<Projector> projector = Projector::create(camera, projection);
  if (!projector) return projector.status();
  Frame frame(camera, std::move(projector).value(), projection);
  frame.draw = &draw;
  frame.stats = &stats;
  frame.faces_only = !settings_.occlusion_map && !draw;
  frame.clear_key = frame.projector.clearKey();
  frame.snap_pixels = settings_.snap_pixels;
  frame.key_sign = camera.depth.convention == DepthConvention::Reversed ? -1.0 : 1.0;
  const bool zero_to_one = camera.depth.clip_range == ClipDepthRange::ZeroToOne;
  frame.depth_scale = zero_to_one ? 1.0 : 0.5;
  frame.depth_offset = zero_to_one ? 0.0 : 0.5;
  // Near plane: z >= -w (standard, -1..1), z >= 0 (standard, 0..1), z <= w (reversed).
  const double ge_low[4] = {0, 0, 1, zero_to_one ? 0.0 : 1.0}, le_one[4] = {0, 0, -1, 1};
  std::copy_n(camera.depth.convention == DepthConvention::Reversed ? le_one : ge_low, 4,
              frame.near_plane);

  // The eye: the point the clip-space x, y and w rows all vanish at (a 4D cross product
  // of those rows). At infinity for an orthographic camera: then a direction.
  const double* m = camera.view_projection.m;
  const int rows[3] = {0, 1, 3};
  double null[4];
  for (int i = 0; i < 4; ++i) {
    double minor[3][3];
    for (int r = 0; r < 3; ++r) {
      int col = 0;
      for (int c = 0; c < 4; ++c) {
        if (c != i) minor[r][col++] = m[c * 4 + rows[r]];
      }
    }
    null[i] = (i % 2 ? -1.0 : 1.0) * det3(minor);
  }
  const double size = std::fabs(null[0]) + std::fabs(null[1]) + std::fabs(null[2]);
  if (std::fabs(null[3]) > 1e-12 * size) {
    for (int a = 0; a < 3; ++a) frame.eye[a] = null[a] / null[3];
  } else {
    frame.ortho = true;
    // Towards the viewer: the direction along which depth keys shrink.
    const double dz = m[2] * null[0] + m[6] * null[1] + m[10] * null[2];
    const double flip = frame.key_sign * dz > 0 ? -1.0 : 1.0;
    const double len = std::sqrt(null[0] * null[0] + null[1] * null[1] + null[2] * null[2]);
    for (int a = 0; a < 3; ++a) frame.dir[a] = flip * null[a] / len;
  }

  if (settings_.occlusion_map) map_.reset(camera.width, camera.height, frame.clear_key);
  if (++stamp_ == 0) {
    std::fill(object_stamp_.begin(), object_stamp_.end(), 0u);
    stamp_ = 1;
  }
  occluders_.clear();
  if (!octree_.empty() && (!frame.faces_only || with_faces_[0])) {
    visit(0, frame.projector.project(octree_.nodes()[0].bounds), frame);
  }
  finishOccluders(frame);
  stats.occluders = occluders_.size();
  stats.seconds = secondsSince(start);
  return {};
}

void Selector::visit(std::uint32_t n, const BoxProjection& p, Frame& frame) {
  SelectionStats& stats = *frame.stats;
  ++stats.nodes_visited;
  const OctreeNode& node = octree_.nodes()[n];
  switch (p.cls) {
    case ProjectionClass::Outside: ++stats.nodes_view_culled; return;
    case ProjectionClass::CrossesNear: ++stats.nodes_near; break;
    case ProjectionClass::Invalid: break;
    case ProjectionClass::Inside:
      if (p.rect.x1 - p.rect.x0 < std::int64_t{settings_.min_node_pixels} &&
          p.rect.y1 - p.rect.y0 < std::int64_t{settings_.min_node_pixels}) {
        ++stats.nodes_small;
        return;
      }
      if (settings_.occlusion_map) {
        ++stats.map_tests;
        if (map_.occludes(p.rect, p.near_key - p.margin)) {
          ++stats.nodes_occluded;
          return;
        }
      }
      break;
  }
  selectFaces(n, frame);
  if (node.leaf()) {
    ++stats.leaves_visible;
    for (std::uint32_t i = 0; i < node.object_count; ++i) {
      const ObjectId id = octree_.objects()[node.first_object + i];
      if (object_stamp_[id] == stamp_) continue;
      object_stamp_[id] = stamp_;
      ++stats.objects;
      if (*frame.draw) (*frame.draw)(id);
    }
    return;
  }
  double lo[3], hi[3];
  octree_.cellBox(n, lo, hi);
  int octant = 0;
  for (int a = 0; a < 3; ++a) {
    const double mid = octree_.plane(a, node.level + 1u, 2ull * node.cell[a] + 1);
    const bool high = frame.ortho ? frame.dir[a] > 0 : frame.eye[a] >= mid;
    if (high) octant |= 1 << a;
  }
  // The children front to back, projected in one call.
  std::uint32_t children[8];
  Aabb boxes[8];
  std::size_t count = 0;
  for (int k : kOrder) {
    const std::uint32_t child = octree_.child(n, octant ^ k);
    if (child == Octree::kNone) continue;
    if (frame.faces_only && !with_faces_[child]) {
      ++stats.nodes_faceless;
      continue;
    }
    children[count] = child;
    boxes[count] = octree_.nodes()[child].bounds;
    ++count;
  }
  BoxProjection projections[8];
  frame.projector.project(boxes, count, projections);
  for (std::size_t i = 0; i < count; ++i) visit(children[i], projections[i], frame);
}

void Selector::selectFaces(std::uint32_t n, Frame& frame) {
  SelectionStats& stats = *frame.stats;
  for (int f = 0; f < kFaces; ++f) {
    const std::uint64_t mask = octree_.mask(n, f);
    if (!mask) continue;
    const FaceFrame fr = octree_.face(n, f);
    if (!seesValidRegion(mask, fr, frame)) continue;
    ++stats.faces_valid;
    BoxProjection cone;
    if (!coneProjection(fr, frame, cone)) continue;
    Face face;
    face.face = f;
    FaceOutline outline;
    if (!faceOnScreen(fr, frame, cone, face, outline)) continue;
    if (!depthPlane(outline, frame.clear_key, face)) continue;
    if (face.safe) {
      std::copy(&outline.win[0][0], &outline.win[0][0] + 8, &face.window[0][0]);
    } else if (!shrinkQuad(outline.win, 2.0 * settings_.snap_pixels, face.window)) {
      continue;
    }
    ++stats.faces_selected;
    if (settings_.occlusion_map) {
      stats.map_pixels +=
          map_.insertQuad(face.window, face.plane_key[0], face.plane_key[1], face.plane_key[2]);
    }
    frame.faces.push_back(face);
  }
}

bool Selector::seesValidRegion(std::uint64_t mask, const FaceFrame& fr, const Frame& frame) const {
  const RegionLayout& layout = octree_.layout();
  const double m = fr.margin;
  // The slopes under which the anchors of the enlarged face see the viewpoint.
  double s1lo, s1hi, s2lo, s2hi;
  if (frame.ortho) {
    const double dh = fr.dir * frame.dir[fr.axis];
    if (!(dh > 0)) return false;
    s1lo = s1hi = frame.dir[fr.t1] / dh;
    s2lo = s2hi = frame.dir[fr.t2] / dh;
  } else {
    const double h = fr.heightOf(frame.eye);
    if (!(h >= fr.height)) return false;  // not beyond the clipping plane
    s1lo = (frame.eye[fr.t1] - (fr.hi1 + m)) / h;
    s1hi = (frame.eye[fr.t1] - (fr.lo1 - m)) / h;
    s2lo = (frame.eye[fr.t2] - (fr.hi2 + m)) / h;
    s2hi = (frame.eye[fr.t2] - (fr.lo2 - m)) / h;
  }
  int b1a, b1b, b2a, b2b;
  RegionLayout::binsMeeting(layout.bins1(), s1lo, s1hi, b1a, b1b);
  RegionLayout::binsMeeting(layout.bins2(), s2lo, s2hi, b2a, b2b);
  for (int b1 = b1a; b1 <= b1b; ++b1) {
    for (int b2 = b2a; b2 <= b2b; ++b2) {
      const std::uint32_t r = layout.region(std::uint32_t(b1), std::uint32_t(b2));
      if ((mask >> r) & 1u) return true;
    }
  }
  return false;
}

namespace {

// Grows `box` by the float box around a double point (one float step outwards).
void growOutwards(Aabb& box, const double* p) {
  const float lo[3] = {std::nextafter(float(p[0]), -HUGE_VALF),
                       std::nextafter(float(p[1]), -HUGE_VALF),
                       std::nextafter(float(p[2]), -HUGE_VALF)};
  const float hi[3] = {std::nextafter(float(p[0]), HUGE_VALF),
                       std::nextafter(float(p[1]), HUGE_VALF),
                       std::nextafter(float(p[2]), HUGE_VALF)};
  box.min = {std::min(box.min.x, lo[0]), std::min(box.min.y, lo[1]), std::min(box.min.z, lo[2])};
  box.max = {std::max(box.max.x, hi[0]), std::max(box.max.y, hi[1]), std::max(box.max.z, hi[2])};
}

const Aabb kNoBox{{HUGE_VALF, HUGE_VALF, HUGE_VALF}, {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF}};

}  // namespace

bool Selector::coneProjection(const FaceFrame& fr, const Frame& frame, BoxProjection& out) {
  // The geometry that hides the face lies, along the rays from the eye through the
  // enlarged face, between the face and the clipping plane: inside the convex hull of
  // the face's corners and the points where those rays cross the clipping plane. That
  // hull must lie in front of the near plane (nothing of it clipped or behind the eye);
  // its box's projection margin bounds the stored depth of that geometry.
  const double m = fr.margin;
  double cone[8][3];
  for (int i = 0; i < 4; ++i) {
    double* q = cone[i];
    double* top = cone[4 + i];
    fr.toWorld(0, (i & 1) ? fr.hi1 + m : fr.lo1 - m, (i & 2) ? fr.hi2 + m : fr.lo2 - m, q);
    q[fr.axis] = fr.plane;
    if (frame.ortho) {
      const double t = fr.height / (fr.dir * frame.dir[fr.axis]);
      for (int a = 0; a < 3; ++a) top[a] = q[a] + t * frame.dir[a];
    } else {
      const double t = fr.height / fr.heightOf(frame.eye);
      for (int a = 0; a < 3; ++a) top[a] = q[a] + t * (frame.eye[a] - q[a]);
    }
    if (!frame.inFrontOfNear(q) || !frame.inFrontOfNear(top)) return false;
  }
  Aabb cone_box = kNoBox;
  for (const auto& p : cone) growOutwards(cone_box, p);
  out = frame.projector.project(cone_box);
  // Outside: the face cannot be seen. A box the projector gave up on (margin 0 while
  // crossing the near plane) has no usable margin.
  return !(out.cls == ProjectionClass::Outside || out.cls == ProjectionClass::Invalid ||
           (out.cls == ProjectionClass::CrossesNear && !(out.margin > 0)));
}

bool Selector::faceOnScreen(const FaceFrame& fr, const Frame& frame, const BoxProjection& cone,
                            Face& face, FaceOutline& o) {
  // The face and the enlarged face on screen.
  const double m = fr.margin;
  face.axis = fr.axis, face.t1 = fr.t1, face.t2 = fr.t2;
  face.plane = fr.plane;
  face.lo1 = fr.lo1, face.hi1 = fr.hi1, face.lo2 = fr.lo2, face.hi2 = fr.hi2;
  const double u[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  Aabb face_box = kNoBox;
  for (int i = 0; i < 4; ++i) {
    double p[3], q[3], k_plus;
    fr.toWorld(0, u[i][0] ? fr.hi1 : fr.lo1, u[i][1] ? fr.hi2 : fr.lo2, p);
    p[fr.axis] = fr.plane;
    fr.toWorld(0, u[i][0] ? fr.hi1 + m : fr.lo1 - m, u[i][1] ? fr.hi2 + m : fr.lo2 - m, q);
    q[fr.axis] = fr.plane;
    const bool in_front =
        frame.toWindow(p, o.win[i], o.key[i]) && frame.toWindow(q, o.win_plus[i], k_plus);
    const double qf[3] = {double(float(q[0])), double(float(q[1])), double(float(q[2]))};
    growOutwards(face_box, qf);
    if (!in_front) return false;
  }
  const BoxProjection face_p = frame.projector.project(face_box);
  if (face_p.cls != ProjectionClass::Inside) return false;
  face.delta = 2.0 * (double(cone.margin) + double(face_p.margin));

  // Width of the band between the face and the enlarged face, on screen.
  double band = HUGE_VAL;
  for (int i = 0; i < 4; ++i) {
    band = std::min(band, pointQuadBoundaryDistance(o.win[i], o.win_plus));
    band = std::min(band, pointQuadBoundaryDistance(o.win_plus[i], o.win));
  }
  face.safe = band >= 2.0 * frame.snap_pixels;
  return true;
}

bool Selector::depthPlane(const FaceOutline& o, float clear_key, Face& face) {
  // The depth plane over window coordinates from the largest corner triangle, moved up
  // by the fourth corner's residual (rounding) and pushed back by delta.
  const auto& win = o.win;
  const auto& key = o.key;
  int skip = 0;
  double best = -1;
  for (int s = 0; s < 4; ++s) {
    const double* a = win[(s + 1) % 4];
    const double* b = win[(s + 2) % 4];
    const double* c = win[(s + 3) % 4];
    const double area = std::fabs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
    if (area > best) best = area, skip = s;
  }
  if (!(best > 0)) return false;  // seen edge-on
  const int i0 = (skip + 1) % 4, i1 = (skip + 2) % 4, i2 = (skip + 3) % 4;
  const double dx1 = win[i1][0] - win[i0][0], dy1 = win[i1][1] - win[i0][1];
  const double dx2 = win[i2][0] - win[i0][0], dy2 = win[i2][1] - win[i0][1];
  const double dk1 = key[i1] - key[i0], dk2 = key[i2] - key[i0];
  const double det = dx1 * dy2 - dx2 * dy1;
  const double b = (dk1 * dy2 - dk2 * dy1) / det, c = (dx1 * dk2 - dx2 * dk1) / det;
  double a = key[i0] - b * win[i0][0] - c * win[i0][1];
  const double residual = key[skip] - (a + b * win[skip][0] + c * win[skip][1]);
  a += std::max(0.0, residual) + face.delta;
  face.plane_key[0] = a, face.plane_key[1] = b, face.plane_key[2] = c;
  double farthest = -HUGE_VAL;
  for (int i = 0; i < 4; ++i) farthest = std::max(farthest, a + b * win[i][0] + c * win[i][1]);
  return farthest < double(clear_key);  // else pushed beyond the far plane
}

void Selector::finishOccluders(Frame& frame) {
  std::vector<Face>& faces = frame.faces;
  auto emit = [&](const double window[4][2], const double* plane, std::uint32_t count) {
    if (auto o = makeOccluder(window, plane, count, frame.camera, frame.settings)) {
      occluders_.push_back(*o);
    }
  };
  if (!settings_.merge) {
    for (const Face& f : faces) emit(f.window, f.plane_key, 1);
    return;
  }
  for (const Face& f : faces) {
    if (!f.safe) emit(f.window, f.plane_key, 1);
  }
  // Safe faces of one plane and orientation, merged along rows then columns.
  struct Rect {
    double lo1, hi1, lo2, hi2, delta;
    std::uint32_t count;
  };
  std::vector<const Face*> safe;
  for (const Face& f : faces) {
    if (f.safe) safe.push_back(&f);
  }
  std::sort(safe.begin(), safe.end(), [](const Face* a, const Face* b) {
    return a->face != b->face ? a->face < b->face : a->plane < b->plane;
  });
  std::vector<Rect> rects;
  for (std::size_t i = 0; i < safe.size();) {
    std::size_t j = i;
    rects.clear();
    while (j < safe.size() && safe[j]->face == safe[i]->face && safe[j]->plane == safe[i]->plane) {
      rects.push_back({safe[j]->lo1, safe[j]->hi1, safe[j]->lo2, safe[j]->hi2, safe[j]->delta, 1});
      ++j;
    }
    const Face& proto = *safe[i];
    for (int pass = 0; pass < 4; ++pass) {
      const bool along1 = pass % 2 == 0;
      std::sort(rects.begin(), rects.end(), [&](const Rect& a, const Rect& b) {
        if (along1) return std::tie(a.lo2, a.hi2, a.lo1) < std::tie(b.lo2, b.hi2, b.lo1);
        return std::tie(a.lo1, a.hi1, a.lo2) < std::tie(b.lo1, b.hi1, b.lo2);
      });
      std::vector<Rect> merged;
      for (const Rect& r : rects) {
        if (!merged.empty()) {
          Rect& last = merged.back();
          const bool joins = along1 ? (last.lo2 == r.lo2 && last.hi2 == r.hi2 && last.hi1 == r.lo1)
                                    : (last.lo1 == r.lo1 && last.hi1 == r.hi1 && last.hi2 == r.lo2);
          if (joins) {
            (along1 ? last.hi1 : last.hi2) = along1 ? r.hi1 : r.hi2;
            last.delta = std::max(last.delta, r.delta);
            last.count += r.count;
            continue;
          }
        }
        merged.push_back(r);
      }
      rects.swap(merged);
    }
    for (const Rect& r : rects) {
      if (r.count == 1) {
        // Unmerged: the face as selected.
        for (const Face* f : std::vector<const Face*>(safe.begin() + std::ptrdiff_t(i),
                                                      safe.begin() + std::ptrdiff_t(j))) {
          if (f->lo1 == r.lo1 && f->lo2 == r.lo2 && f->hi1 == r.hi1 && f->hi2 == r.hi2) {
            emit(f->window, f->plane_key, 1);
            break;
          }
        }
        continue;
      }
      // The merged rectangle: its corners on screen and its depth plane, pushed back by
      // the largest push of its faces.
      FaceFrame fr;
      fr.axis = proto.axis, fr.t1 = proto.t1, fr.t2 = proto.t2;
      fr.plane = proto.plane;
      double win[4][2], key[4];
      bool ok = true;
      const double corners[4][2] = {{r.lo1, r.lo2}, {r.hi1, r.lo2}, {r.hi1, r.hi2}, {r.lo1, r.hi2}};
      for (int c = 0; c < 4 && ok; ++c) {
        double p[3];
        p[fr.axis] = fr.plane, p[fr.t1] = corners[c][0], p[fr.t2] = corners[c][1];
        ok = frame.toWindow(p, win[c], key[c]);
      }
      const double dx1 = win[1][0] - win[0][0], dy1 = win[1][1] - win[0][1];
      const double dx2 = win[3][0] - win[0][0], dy2 = win[3][1] - win[0][1];
      const double det = dx1 * dy2 - dx2 * dy1;
      if (!ok || !(std::fabs(det) > 0)) continue;
      const double dk1 = key[1] - key[0], dk2 = key[3] - key[0];
      const double b = (dk1 * dy2 - dk2 * dy1) / det, c = (dx1 * dk2 - dx2 * dk1) / det;
      double a = key[0] - b * win[0][0] - c * win[0][1];
      a += std::max(0.0, key[2] - (a + b * win[2][0] + c * win[2][1])) + r.delta;
      const double plane[3] = {a, b, c};
      emit(win, plane, r.count);
    }
    i = j;
  }
}

}  // namespace logrid::ddo
