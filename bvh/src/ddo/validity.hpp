// The validity test of one face for all its regions (DDO §3.2; the criterion is stated
// in logrid/ddo/build.hpp). Internal to the preprocessing.
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/ddo/mesh.hpp"
#include "logrid/ddo/regions.hpp"
#include "segment_index.hpp"
#include "topology.hpp"

namespace logrid::ddo::detail {

struct FaceCounters {
  std::uint64_t regions_tested = 0;
  std::uint64_t regions_valid = 0;
  std::uint64_t regions_degenerate = 0;
  std::uint64_t pieces_followed = 0;
  std::uint64_t pieces_abandoned = 0;
  std::uint64_t piece_triangles = 0;  // triangles the pieces' searches took from their queues
  std::uint64_t closed_even = 0;      // closed pieces crossed an even number of times
  std::uint64_t open_pieces = 0;      // pieces with a free edge inside the frustum
  std::uint64_t corner_misses = 0;    // regions ruled out by an edge of P crossing nothing
};

// Per-thread working memory.
struct FaceScratch {
  std::vector<std::uint32_t> stamp;  // per triangle: the piece that last reached it
  std::vector<std::uint32_t> order;  // per triangle: its place in that piece's queue
  std::uint32_t next_stamp = 1;
  std::vector<std::uint32_t> queue;
  std::vector<SegmentHit> hits;
  std::vector<std::uint32_t> stack;
};

class FaceTester {
 public:
  FaceTester(const SceneMesh& mesh, const MeshTopology& topology, const SegmentIndex& index,
             const RegionLayout& layout, std::uint32_t max_piece_triangles)
      : mesh_(mesh),
        topology_(topology),
        index_(index),
        layout_(layout),
        max_piece_(max_piece_triangles) {}

  void prepare(FaceScratch& scratch) const;
  // Bit r set: the face is a valid occluder for region r.
  std::uint64_t validRegions(const FaceFrame& face, FaceScratch& scratch,
                             FaceCounters& counters) const;
  // The same for one region.
  bool validRegion(const FaceFrame& face, std::uint32_t region, FaceScratch& scratch,
                   FaceCounters& counters) const;

 private:
  // validRegion's steps. crossTestSegment: the test segment's crossings into
  // scratch.hits (false: every segment grazed an edge). cornerEdgesMeetAny: each of P's
  // four edges along its height meets a triangle of the slab. crossedPieceIsValid: a
  // piece the segment crosses is closed inside P and crossed an odd number of times.
  bool crossTestSegment(const FaceFrame& face, const SlopeCell& cell, const Slab& slab,
                        FaceScratch& scratch) const;
  bool cornerEdgesMeetAny(const FaceFrame& face, const SlopeCell& cell, const Slab& slab,
                          FaceScratch& scratch) const;
  bool crossedPieceIsValid(const ViewspaceFrustum& frustum, const Slab& slab, double face_height,
                           FaceScratch& scratch, FaceCounters& counters) const;
  // The piece of the slab's triangles reached from `seed` across edges inside P, stamped
  // `s`; each triangle taken from the queue spends one of `budget`.
  enum class PieceEnd : std::uint8_t { Closed, Open, OverBudget };
  PieceEnd followPiece(std::uint32_t seed, std::uint32_t s, const ViewspaceFrustum& frustum,
                       const Slab& slab, double tolerance, std::uint64_t& budget,
                       FaceScratch& scratch, FaceCounters& counters) const;

  const SceneMesh& mesh_;
  const MeshTopology& topology_;
  const SegmentIndex& index_;
  RegionLayout layout_;
  std::uint32_t max_piece_;
};

}  // namespace logrid::ddo::detail
