// What the parts of a culled frame cost on the running machine: the cost model the `auto`
// method chooses with (docs/AUTO.md).
//
// Every figure is seconds of wall time, for one unit of work:
//   flush_s     waiting for the renderer once (a depth read or a query result that made it
//               finish its pending work), net of the pixels read; measured after a
//               near-empty draw, so it is the synchronisation, not the drawing it waits for
//   pixel_s     one more depth pixel read (or counted) once the renderer is waited for
//   box_test_s  one box taken through the traversal and its records on the CPU
//               (projection, test-list, grid records), no read
//   triangle_s  one triangle drawn
//   draw_s      one object drawn beyond its triangles (the draw call)
//   query_s     one hardware occlusion query issued and answered, its flush excluded
// The costs of a depth source differ by source (a PBO ring, a compute reduction, a
// query); `logrid calibrate --costs FILE` measures one set per source and writes them in
// the file format below, which loadCullerCosts() reads.
//
// The file (JSON; unknown keys are ignored, every cost must be present):
//   { "format": "logrid-costs", "version": 1, "machine": "...",
//     "sources": { "readpixels": { "flush_s": 4.1e-5, "pixel_s": 2.2e-9, "box_test_s": 1.5e-7,
//                                  "triangle_s": 1.9e-8, "draw_s": 3.1e-6, "query_s": 2.4e-5 },
//                  "pbo": { ... } } }
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "logrid/error.hpp"
#include "logrid/stats.hpp"

namespace logrid {

// Defaults: the 2-core build machine's llvmpipe with the readpixels source (docs/AUTO.md);
// the `auto` method refines them online from its own frames (CostEstimate).
struct CullerCosts {
  double flush_s = 60e-6;
  double pixel_s = 3e-9;
  double box_test_s = 0.3e-6;
  double triangle_s = 25e-9;
  double draw_s = 4e-6;
  double query_s = 30e-6;
};

// Empty if every cost is finite and in (0, 1] second, else a message naming the field.
std::string validateCullerCosts(const CullerCosts& costs);

// A costs file: one set per depth source, by the source's name (DepthSourceTraits::name).
struct CullerCostsFile {
  std::string machine;  // what measured them (renderer, CPU), as calibrate wrote it
  std::map<std::string, CullerCosts> sources;
};

// Parses a costs file's text; `origin` names it in messages. ErrorCode::BadInput for text
// that is not such a file: not JSON, another format or version, no sources, a cost
// missing, not a number or out of range; the message names the origin, the source and
// the field. Both forms (error.hpp), as the two below.
Result<CullerCostsFile> tryParseCullerCosts(const std::string& text,
                                            const std::string& origin = "costs");
CullerCostsFile parseCullerCosts(const std::string& text, const std::string& origin = "costs");
// Reads and parses a costs file (ErrorCode::Environment if it cannot be read).
Result<CullerCostsFile> tryLoadCullerCostsFile(const std::string& path);
CullerCostsFile loadCullerCostsFile(const std::string& path);
// The costs of one source from a file; ErrorCode::BadInput naming the sources the file
// has if `source` is not among them.
Result<CullerCosts> tryLoadCullerCosts(const std::string& path, const std::string& source);
CullerCosts loadCullerCosts(const std::string& path, const std::string& source);
// The file's text, which parseCullerCosts reads back as `file` (every cost to the bit).
std::string formatCullerCosts(const CullerCostsFile& file);

#if LOGRID_HAS_EXCEPTIONS
inline CullerCostsFile parseCullerCosts(const std::string& text, const std::string& origin) {
  return orThrow(tryParseCullerCosts(text, origin));
}
inline CullerCostsFile loadCullerCostsFile(const std::string& path) {
  return orThrow(tryLoadCullerCostsFile(path));
}
inline CullerCosts loadCullerCosts(const std::string& path, const std::string& source) {
  return orThrow(tryLoadCullerCosts(path, source));
}
#endif

// An online estimate of the costs from a culler's own frames (Culler::costEstimate):
// each frame's wall time is explained as flushes x flush_s + pixels x pixel_s + boxes
// tested x box_test_s + triangles x triangle_s + objects x draw_s + queries x query_s,
// and a factor per cost is fitted by least squares over the recent frames (weights
// decaying by `decay` a frame), held near the prior where the frames say little
// (ridge), and kept within [1/16, 16] of it. What the frames cannot tell apart (two
// counts that always move together) stays as the prior sets it.
class CostEstimate {
 public:
  explicit CostEstimate(const CullerCosts& prior = {}, double decay = 0.95);

  // Takes one frame's counters and its FrameStats::seconds.
  void update(const FrameStats& frame);
  const CullerCosts& costs() const { return costs_; }
  const CullerCosts& prior() const { return prior_; }
  std::uint64_t frames() const { return frames_; }
  // The fit's prediction of a frame's seconds from its counters.
  double predict(const FrameStats& frame) const;

  static constexpr int kTerms = 6;

 private:
  CullerCosts prior_;
  CullerCosts costs_;
  double decay_;
  std::uint64_t frames_ = 0;
  double a_[kTerms][kTerms] = {};  // decayed sums of z z^T (z: the prior's seconds per term)
  double b_[kTerms] = {};          // decayed sums of z y
};

}  // namespace logrid
