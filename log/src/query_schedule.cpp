#include "logrid/query_schedule.hpp"

#include <cmath>
#include <sstream>

#include "query_frame.hpp"

namespace logrid {

std::string validateHardwareParameters(const HardwareParameters& p) {
  const struct {
    const char* name;
    double value;
    bool positive;
  } fields[] = {
      {"render_setup", p.render_setup, true},        {"render_triangle", p.render_triangle, false},
      {"render_fragment", p.render_fragment, false}, {"query_setup", p.query_setup, true},
      {"query_fragment", p.query_fragment, false},   {"query_latency", p.query_latency, false},
      {"query_overhead", p.query_overhead, false},   {"poll", p.poll, false}};
  for (const auto& f : fields) {
    if (!std::isfinite(f.value) || f.value < 0 || (f.positive && !(f.value > 0))) {
      std::ostringstream out;
      out << "hardware parameter " << f.name << " is " << f.value << " s; nohc needs every time "
          << "finite and >= 0, render_setup and query_setup > 0: measure them on the context with "
             "zread::calibrateQueries() (logrid calibrate prints them)";
      return out.str();
    }
  }
  return {};
}

std::string validateQuerySchedule(Method method, const QueryScheduleDesc& d) {
  Method schedule = method;
  if (method == Method::LogHwq) {
    schedule = d.schedule;
    if (schedule != Method::Hwq && schedule != Method::Chc && schedule != Method::Stat &&
        schedule != Method::Nohc) {
      return std::string("queries.schedule ") + toString(schedule) +
             " is not a query schedule; log+hwq takes hwq, chc, stat or nohc";
    }
  }
  if (d.shape != QueryShape::Box && d.shape != QueryShape::Rect) {
    return "queries.shape has the unknown value " + std::to_string(int(d.shape));
  }
  switch (schedule) {
    case Method::Chc:
      if (d.chc_batch < 1) return "queries.chc_batch 0 is invalid; use 1 or more nodes";
      if (d.chc_visible_interval < 1) {
        return "queries.chc_visible_interval 0 is invalid; use 1 or more frames";
      }
      break;
    case Method::Stat:
      if (d.stat_in_flight < 1) return "queries.stat_in_flight 0 is invalid; use 1 or more";
      if (d.stat_base_frames < 1) return "queries.stat_base_frames 0 is invalid; use 1 or more";
      break;
    case Method::Nohc: return validateHardwareParameters(d.hardware);
    default: break;
  }
  return {};
}

namespace detail {

std::unique_ptr<QuerySchedule> makeHwqSchedule();
std::unique_ptr<QuerySchedule> makeChcSchedule(const QueryScheduleDesc& d);
std::unique_ptr<QuerySchedule> makeStatSchedule(const QueryScheduleDesc& d);
std::unique_ptr<QuerySchedule> makeNohcSchedule(const QueryScheduleDesc& d);

std::unique_ptr<QuerySchedule> makeQuerySchedule(const CullerDesc& desc) {
  const Method schedule = desc.method == Method::LogHwq ? desc.queries.schedule : desc.method;
  switch (schedule) {
    case Method::Hwq: return makeHwqSchedule();
    case Method::Chc: return makeChcSchedule(desc.queries);
    case Method::Stat: return makeStatSchedule(desc.queries);
    case Method::Nohc: return makeNohcSchedule(desc.queries);
    default: return nullptr;
  }
}

}  // namespace detail
}  // namespace logrid
