// The culling methods logrid offers, each defined in one place: its own file in
// log/src/methods/, registered in the table of log/src/methods/registry.cpp. What a method
// is (its traversal, test semantics, grid variant), what cullFrame() must be given for it
// (CullSources) and which CullerDesc settings it takes are read from its MethodInfo by the
// culler, the command line, the benchmark and the viewer alike; none of them switches on
// the method itself. docs/DESIGN.md ("The methods") describes each method beside its paper.
//
// Adding a method: a name in the enum below, a file in log/src/methods/ with its
// MethodDef (log/src/methods/method_def.hpp), and its line in the table.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "logrid/grid_settings.hpp"
#include "logrid/query_schedule.hpp"

namespace logrid {

enum class Method : std::uint8_t {
  LogState,  // lazy occlusion grid, occlusion-state variant, two-list traversal (LOG §3)
  LogZfar,   // lazy occlusion grid, zfar variant, approximate traversal (LOG §4)
  Bog,       // busy occlusion grid: tiles refreshed right after each draw (LOG §5)
  Hzb,       // hierarchical z-buffer refreshed from the drawn box's area after each draw
  Pq,        // one pixel-level query over each tested box's whole rectangle
  Vfc,       // view-frustum culling only
  Hwq,       // stop and wait: one hardware occlusion query per tested box
  Chc,       // coherent hierarchical culling, CHC++ (Mattausch, Bittner, Wimmer 2008)
  Stat,      // statistically optimised queries (Kovalčík & Sochor 2005)
  Nohc,      // near-optimal hierarchical culling (Guthe, Balázs, Klein 2006)
  LogHwq,    // the lazy grid's records decide what they can; the rest is queried
  Ddo,       // boxes tested against the CPU map of directional discretized occluders
  DdoLog,    // log-state, with the cells those occluders cover recorded hidden, unread
  Auto,      // chooses log-state or log-zfar, K and coherence per frame, and per node
             // whether a test pays, from measured costs (costs.hpp, docs/AUTO.md)
};

// How a method walks the hierarchy (culler.hpp).
enum class Traversal : std::uint8_t {
  TwoList,      // LOG §3: test-list by nearest key, draw-list by farthest key; a visible
                // node is drawn once it lies in front of every box still to be tested
  FrontToBack,  // approximate front to back: visible nodes are drawn at once (LOG §4)
  Schedule,     // a hardware-query schedule decides when to query (query_schedule.hpp)
};

// What an occlusion test counts as hiding a box.
enum class TestSemantics : std::uint8_t {
  None,            // no occlusion test: view-frustum culling only
  OcclusionState,  // every pixel of the box holds something drawn; sound only while
                   // everything drawn lies in front of the box (the two-list order)
  Depth,           // every pixel of the box is nearer than the box's nearest depth;
                   // sound in any order
};

// An occluder pre-pass (CullSources::occluders, occluder_source.hpp).
enum class OccluderUse : std::uint8_t {
  None,
  Map,       // the occluders' CPU map decides the tests; nothing is drawn or read (ddo)
  Recorded,  // the tiles the occluders cover are recorded hidden behind them, without a
             // read or a draw (ddo+log; OcclusionGrid::recordCovered)
};

// What cullFrame() must be given for the method (CullSources).
struct MethodNeeds {
  bool depth = false;         // a DepthSource
  bool depth_values = false;  // one that answers Summary requests (DepthSourceTraits::reads_depth)
  bool queries = false;       // OcclusionQueries
  bool occluders = false;     // an OccluderSource
};

// Which CullerDesc settings the method uses (the others are ignored, or, for the
// approximate knobs, refused by validateCullerDesc).
struct MethodTakes {
  bool lookahead = false;           // CullerDesc::lookahead (tests batched across boxes)
  bool temporal_coherence = false;  // CullerDesc::temporal_coherence
  bool query_schedule = false;      // CullerDesc::queries.schedule (log+hwq)
  bool visible_pixels = false;      // GridApproximation::visible_pixels
  bool full_fraction = false;       // GridApproximation::full_free_fraction
  bool row_stride = false;          // GridApproximation::row_stride
};

struct MethodInfo {
  Method method = Method::LogState;
  const char* name = "";         // as parsed and printed, e.g. "log-state"
  const char* description = "";  // one line
  Traversal traversal = Traversal::FrontToBack;
  TestSemantics semantics = TestSemantics::None;
  std::optional<GridVariant> grid;  // the lazy (or busy) occlusion grid it keeps, if any
  // Traversal::Schedule: the query schedule it runs; none for log+hwq, which runs
  // CullerDesc::queries.schedule (MethodTakes::query_schedule).
  std::optional<QuerySchedule> schedule;
  OccluderUse occluders = OccluderUse::None;
  MethodNeeds needs;
  MethodTakes takes;
};

// Every method, in the order of the enum.
const std::vector<MethodInfo>& methodTable();
const MethodInfo& methodInfo(Method method);  // asserts on a value outside the enum
const char* toString(Method method);
// Parses a method's name; nothing for an unknown one.
std::optional<Method> parseMethod(const std::string& name);
// "log-state, log-zfar, ..., ddo+log" for messages and help texts.
std::string methodNames();

}  // namespace logrid
