// The culling methods logrid compares (docs/DESIGN.md, "The methods"), each
// described in one place: the table in method.cpp. The culler, the command line and
// the benchmark read what a method needs from here; each method's occlusion test
// lives in one class of log/src/testers.cpp.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace logrid {

enum class Method : std::uint8_t {
  LogState,  // lazy occlusion grid, occlusion-state variant, two-list traversal (LOG §3)
  LogZfar,   // lazy occlusion grid, zfar variant, approximate traversal (LOG §4)
  Bog,       // busy occlusion grid: tiles refreshed right after each draw (LOG §5)
  Hzb,       // hierarchical z-buffer refreshed from the drawn box's area after each draw
  Pq,        // one pixel-level query over each tested box's whole rectangle
  Vfc,       // view-frustum culling only
  // Hardware occlusion queries (occlusion_queries.hpp), one schedule each in log/src/query_*.cpp:
  Hwq,     // stop and wait: one query per tested box, its answer waited for at once
  Chc,     // coherent hierarchical culling, CHC++ (Mattausch, Bittner, Wimmer 2008)
  Stat,    // statistically optimised queries (Kovalčík & Sochor 2005)
  Nohc,    // near-optimal hierarchical culling (Guthe, Balázs, Klein 2006)
  LogHwq,  // the lazy grid's records decide what they can; the rest is queried
};

// What the traversal and the command line need to know about a method.
struct MethodInfo {
  Method method;
  const char* name;         // as parsed and printed, e.g. "log-state"
  const char* description;  // one line
  // The two-list order of LOG §3 (test-list by nearest key, draw-list by farthest key):
  // a visible node is drawn once it lies in front of every box still to be tested.
  // Otherwise visible nodes are drawn at once (approximate front to back, LOG §4).
  bool two_list_order;
  // Occlusion-state semantics: a box is hidden where every pixel holds anything drawn,
  // which is sound only while everything drawn lies in front of it (the two-list order
  // guarantees it). Otherwise boxes are tested against depths (their nearest key).
  bool state_semantics;
  bool tests_occlusion;     // false: view-frustum culling only
  bool needs_depth_values;  // needs a source that answers Summary requests and readKeys()
  bool lookahead;           // tests can be batched across boxes (CullerDesc::lookahead)
  bool uses_depth_source;   // reads the depth buffer through a DepthSource
  bool box_queries;         // issues hardware occlusion queries through OcclusionQueries
  // The approximate knobs (GridApproximation) it takes.
  bool takes_visible_pixels;
  bool takes_full_fraction;
  bool takes_row_stride;
};

// Every method, in the order of the enum.
const std::vector<MethodInfo>& methodTable();
const MethodInfo& methodInfo(Method method);  // asserts on a value outside the enum
const char* toString(Method method);
// Parses a method's name; nothing for an unknown one.
std::optional<Method> parseMethod(const std::string& name);
// "log-state, log-zfar, ..., vfc" for messages and help texts.
std::string methodNames();

}  // namespace logrid
