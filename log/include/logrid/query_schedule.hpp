// Settings of the hardware-occlusion-query methods (method.hpp: hwq, chc, stat, nohc and
// log+hwq), CullerDesc::queries. Each schedule lives in one file, log/src/query_*.cpp,
// whose header comment cites the paper section it follows.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace logrid {

// The hardware-query schedules. The methods hwq, chc, stat and nohc each run theirs over
// the whole hierarchy; log+hwq runs QueryScheduleDesc::schedule over the boxes its grid's
// records leave undecided.
enum class QuerySchedule : std::uint8_t {
  Hwq,   // stop and wait: each query's answer waited for at once
  Chc,   // CHC++ (Mattausch, Bittner, Wimmer 2008)
  Stat,  // statistically optimised queries (Kovalčík & Sochor 2005)
  Nohc,  // near-optimal hierarchical culling (Guthe, Balázs, Klein 2006)
};

const char* toString(QuerySchedule schedule);
// Parses "hwq", "chc", "stat" or "nohc"; nothing for another name.
std::optional<QuerySchedule> parseQuerySchedule(const std::string& name);
// "hwq, chc, stat, nohc" for messages and help texts.
std::string querySchedules();

// The hardware-dependent times of Guthe et al.'s cost model (NOHC §3.2, Table 2), in
// seconds, measured on the current context at start-up (zread/calibration.hpp). The
// method nohc needs them; the other methods ignore them.
struct HardwareParameters {
  double render_setup = 0;     // T_r^s  setup time per rendering call
  double render_triangle = 0;  // T_r^Δ  time per rendered triangle
  double render_fragment = 0;  // T_r^f  time per shaded fragment
  double query_setup = 0;      // T_o^s  setup time per occlusion query
  double query_fragment = 0;   // T_o^f  time per fragment during an occlusion query
  double query_latency = 0;    // T_o^l  maximum occlusion query latency
  double query_overhead = 0;   // T_o^o  overhead of a query issued along with rendering
  // Not in Table 2: one availability poll (§4.3 uses the API's synchronisation only where
  // it is "reasonably fast", which the measurement identifies).
  double poll = 0;
};

// Empty if nohc can use the parameters (every time finite and >= 0, render and query
// setup > 0), else a message naming the field and its value.
std::string validateHardwareParameters(const HardwareParameters& p);

// What a query draws (occlusion_queries.hpp).
enum class QueryShape : std::uint8_t {
  Box,   // the faces of the widened box (Projector::queryBox): tight
  Rect,  // the box's pixel rectangle at its nearest depth: one quad, looser
};

struct QueryScheduleDesc {
  // log+hwq: the schedule of the boxes the grid's records leave undecided.
  QuerySchedule schedule = QuerySchedule::Stat;
  QueryShape shape = QueryShape::Box;
  // chc (CHC++ §3.2, §4): previously invisible nodes gathered before their multi-queries
  // are issued, and n_av, the frames a visible leaf goes without a query (the first
  // interval after turning visible is drawn at random from 1..n_av).
  std::uint32_t chc_batch = 50;
  std::uint32_t chc_visible_interval = 5;
  // stat (Kovalčík & Sochor §3): queries issued before the second pass over the queue
  // collects them ("about 20"), and BASE_TIME in frames (the paper's 2/3 s at 30 Hz).
  std::uint32_t stat_in_flight = 20;
  std::uint32_t stat_base_frames = 20;
  // nohc (Guthe et al. §3-4): Table 2 of this renderer.
  HardwareParameters hardware;
};

// Empty if the settings are usable for `schedule`, else a message naming the field.
std::string validateQuerySchedule(QuerySchedule schedule, const QueryScheduleDesc& desc);

}  // namespace logrid
