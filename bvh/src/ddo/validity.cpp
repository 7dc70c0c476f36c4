#include "validity.hpp"

#include <algorithm>
#include <cmath>

namespace logrid::ddo::detail {
namespace {

// Where the test segment meets the top cap and the face, as fractions of their lateral
// extents: the axis first, then points moved off it for when the axis grazes an edge.
constexpr double kSegmentFractions[][4] = {{0.5, 0.5, 0.5, 0.5},
                                           {0.5137, 0.4711, 0.5273, 0.4859},
                                           {0.3719, 0.6281, 0.4127, 0.5903},
                                           {0.6457, 0.3361, 0.6031, 0.3839}};

void vertexOf(const SceneMesh& mesh, std::uint32_t t, int k, double* out) {
  const float* p = mesh.vertex(mesh.corner(t, k));
  out[0] = p[0], out[1] = p[1], out[2] = p[2];
}

}  // namespace

void FaceTester::prepare(FaceScratch& scratch) const {
  scratch.stamp.assign(mesh_.triangleCount(), 0);
  scratch.order.assign(mesh_.triangleCount(), 0);
  scratch.next_stamp = 1;
}

std::uint64_t FaceTester::validRegions(const FaceFrame& face, FaceScratch& scratch,
                                       FaceCounters& counters) const {
  std::uint64_t bits = 0;
  for (std::uint32_t r = 0; r < layout_.count(); ++r) {
    if (validRegion(face, r, scratch, counters)) bits |= std::uint64_t{1} << r;
  }
  return bits;
}

bool FaceTester::validRegion(const FaceFrame& face, std::uint32_t region, FaceScratch& scratch,
                             FaceCounters& counters) const {
  ++counters.regions_tested;
  if (scratch.next_stamp > 0xF0000000u) {  // before the stamps wrap around
    std::fill(scratch.stamp.begin(), scratch.stamp.end(), 0u);
    scratch.next_stamp = 1;
  }
  const SlopeCell cell = layout_.cell(region);
  const Slab slab{face.axis, std::min(face.plane, face.clip_plane),
                  std::max(face.plane, face.clip_plane)};
  if (!crossTestSegment(face, cell, slab, scratch)) {
    ++counters.regions_degenerate;
    return false;
  }
  if (scratch.hits.empty()) return false;
  if (!cornerEdgesMeetAny(face, cell, slab, scratch)) {
    ++counters.corner_misses;
    return false;
  }
  return crossedPieceIsValid(ViewspaceFrustum(face, cell), slab, face.height, scratch, counters);
}

bool FaceTester::crossTestSegment(const FaceFrame& face, const SlopeCell& cell, const Slab& slab,
                                  FaceScratch& scratch) const {
  // The test segment, from the top cap down to the enlarged face; its ends lie exactly
  // on the two planes, which no triangle of the slab touches.
  const double m = face.margin, h = face.height;
  for (const auto& f : kSegmentFractions) {
    double top[3], bottom[3];
    const double top_lo1 = face.lo1 - m + h * cell.lo1, top_hi1 = face.hi1 + m + h * cell.hi1;
    const double top_lo2 = face.lo2 - m + h * cell.lo2, top_hi2 = face.hi2 + m + h * cell.hi2;
    face.toWorld(h, top_lo1 + f[0] * (top_hi1 - top_lo1), top_lo2 + f[1] * (top_hi2 - top_lo2),
                 top);
    top[face.axis] = face.clip_plane;
    face.toWorld(0, face.lo1 - m + f[2] * (face.hi1 - face.lo1 + 2 * m),
                 face.lo2 - m + f[3] * (face.hi2 - face.lo2 + 2 * m), bottom);
    bottom[face.axis] = face.plane;
    scratch.hits.clear();
    if (index_.crossings(top, bottom, slab, topology_, scratch.hits, scratch.stack)) return true;
  }
  return false;
}

bool FaceTester::cornerEdgesMeetAny(const FaceFrame& face, const SlopeCell& cell, const Slab& slab,
                                    FaceScratch& scratch) const {
  // Every path through P from the top cap to the face crosses a valid piece: the four
  // edges of P along its height are such paths, and a clean miss of all of them rules the
  // region out before any piece is followed (most pieces that reach a free edge are
  // walls that end inside P, which these edges pass by).
  const double m = face.margin, h = face.height;
  for (int corner = 0; corner < 4; ++corner) {
    const bool high1 = corner & 1, high2 = corner & 2;
    double low[3], high[3];
    face.toWorld(0, high1 ? face.hi1 + m : face.lo1 - m, high2 ? face.hi2 + m : face.lo2 - m, low);
    low[face.axis] = face.plane;
    face.toWorld(h, high1 ? face.hi1 + m + h * cell.hi1 : face.lo1 - m + h * cell.lo1,
                 high2 ? face.hi2 + m + h * cell.hi2 : face.lo2 - m + h * cell.lo2, high);
    high[face.axis] = face.clip_plane;
    if (!index_.meetsAny(high, low, slab, topology_, scratch.stack)) return false;
  }
  return true;
}

bool FaceTester::crossedPieceIsValid(const ViewspaceFrustum& frustum, const Slab& slab,
                                     double face_height, FaceScratch& scratch,
                                     FaceCounters& counters) const {
  // Rounding may only add edges that meet P (more pieces refused): loosen P by a hair.
  const double tolerance = 1e-7 * face_height;
  // Each crossed triangle seeds a piece unless an earlier piece of this region reached it.
  const std::uint32_t region_first_stamp = scratch.next_stamp;
  std::uint64_t budget = max_piece_;
  for (const SegmentHit& seed : scratch.hits) {
    if (scratch.stamp[seed.triangle] >= region_first_stamp) continue;
    ++counters.pieces_followed;
    const std::uint32_t s = scratch.next_stamp++;
    const PieceEnd end =
        followPiece(seed.triangle, s, frustum, slab, tolerance, budget, scratch, counters);
    if (end == PieceEnd::OverBudget) {
      ++counters.pieces_abandoned;
      return false;
    }
    if (end == PieceEnd::Open) {
      ++counters.open_pieces;
      continue;
    }
    std::uint32_t crossings = 0;
    for (const SegmentHit& hit : scratch.hits) crossings += scratch.stamp[hit.triangle] == s;
    if (crossings % 2 == 1) {
      ++counters.regions_valid;
      return true;
    }
    ++counters.closed_even;
  }
  return false;
}

FaceTester::PieceEnd FaceTester::followPiece(std::uint32_t seed, std::uint32_t s,
                                             const ViewspaceFrustum& frustum, const Slab& slab,
                                             double tolerance, std::uint64_t& budget,
                                             FaceScratch& scratch, FaceCounters& counters) const {
  scratch.stamp[seed] = s;
  scratch.order[seed] = 0;
  scratch.queue.clear();
  scratch.queue.push_back(seed);
  for (std::size_t q = 0; q < scratch.queue.size(); ++q) {
    if (budget-- == 0) return PieceEnd::OverBudget;
    const std::uint32_t t = scratch.queue[q];
    ++counters.piece_triangles;
    for (int k = 0; k < 3; ++k) {
      // A triangle of the piece taken from the queue before this one shares the edge:
      // it has already decided the edge (the test and the count are the same from
      // either side).
      const std::uint32_t h = t * 3 + std::uint32_t(k);
      bool decided = false;
      for (std::uint32_t h2 = topology_.next(h); h2 != h && !decided; h2 = topology_.next(h2)) {
        const std::uint32_t t2 = h2 / 3;
        decided = scratch.stamp[t2] == s && scratch.order[t2] < q;
      }
      if (decided) continue;
      double a[3], b[3];
      vertexOf(mesh_, t, k, a);
      vertexOf(mesh_, t, (k + 1) % 3, b);
      if (!frustum.meetsSegment(a, b, tolerance)) continue;
      // An edge inside P: the piece continues across it, and must be shared by an even
      // number of the slab's triangles (a free edge inside P lets rays through).
      std::uint32_t sharing = 1;
      for (std::uint32_t h2 = topology_.next(h); h2 != h; h2 = topology_.next(h2)) {
        const std::uint32_t t2 = h2 / 3;
        if (scratch.stamp[t2] == s) {  // already in the piece, hence inside the slab
          ++sharing;
          continue;
        }
        if (topology_.degenerate(t2) || !index_.insideSlab(t2, slab)) continue;
        ++sharing;
        scratch.stamp[t2] = s;
        scratch.order[t2] = std::uint32_t(scratch.queue.size());
        scratch.queue.push_back(t2);
      }
      if (sharing % 2 != 0) return PieceEnd::Open;
    }
  }
  return PieceEnd::Closed;
}

}  // namespace logrid::ddo::detail
