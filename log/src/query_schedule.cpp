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

namespace detail {
std::unique_ptr<Schedule> makeHwqSchedule(const QueryScheduleDesc& d);
std::unique_ptr<Schedule> makeChcSchedule(const QueryScheduleDesc& d);
std::unique_ptr<Schedule> makeStatSchedule(const QueryScheduleDesc& d);
std::unique_ptr<Schedule> makeNohcSchedule(const QueryScheduleDesc& d);
}  // namespace detail

namespace {

std::string validateChc(const QueryScheduleDesc& d) {
  if (d.chc_batch < 1) return "queries.chc_batch 0 is invalid; use 1 or more nodes";
  if (d.chc_visible_interval < 1) {
    return "queries.chc_visible_interval 0 is invalid; use 1 or more frames";
  }
  return {};
}

std::string validateStat(const QueryScheduleDesc& d) {
  if (d.stat_in_flight < 1) return "queries.stat_in_flight 0 is invalid; use 1 or more";
  if (d.stat_base_frames < 1) return "queries.stat_base_frames 0 is invalid; use 1 or more";
  return {};
}

std::string validateNohc(const QueryScheduleDesc& d) {
  return validateHardwareParameters(d.hardware);
}

std::string nothingToValidate(const QueryScheduleDesc&) { return {}; }

// Every schedule, in the order of the enum: its name, its implementation (one file each)
// and the checks of its settings.
struct ScheduleDef {
  QuerySchedule schedule;
  const char* name;
  std::unique_ptr<detail::Schedule> (*make)(const QueryScheduleDesc&);
  std::string (*validate)(const QueryScheduleDesc&);
};

constexpr ScheduleDef kSchedules[] = {
    {QuerySchedule::Hwq, "hwq", detail::makeHwqSchedule, nothingToValidate},
    {QuerySchedule::Chc, "chc", detail::makeChcSchedule, validateChc},
    {QuerySchedule::Stat, "stat", detail::makeStatSchedule, validateStat},
    {QuerySchedule::Nohc, "nohc", detail::makeNohcSchedule, validateNohc},
};

const ScheduleDef* find(QuerySchedule schedule) {
  for (const ScheduleDef& s : kSchedules) {
    if (s.schedule == schedule) return &s;
  }
  return nullptr;
}

}  // namespace

const char* toString(QuerySchedule schedule) {
  const ScheduleDef* s = find(schedule);
  return s ? s->name : "?";
}

std::optional<QuerySchedule> parseQuerySchedule(const std::string& name) {
  for (const ScheduleDef& s : kSchedules) {
    if (name == s.name) return s.schedule;
  }
  return std::nullopt;
}

std::string querySchedules() {
  std::string out;
  for (const ScheduleDef& s : kSchedules) out += std::string(out.empty() ? "" : ", ") + s.name;
  return out;
}

std::string validateQuerySchedule(QuerySchedule schedule, const QueryScheduleDesc& d) {
  const ScheduleDef* s = find(schedule);
  if (!s) {
    return "queries.schedule has the unknown value " + std::to_string(int(schedule)) + "; use " +
           querySchedules();
  }
  if (d.shape != QueryShape::Box && d.shape != QueryShape::Rect) {
    return "queries.shape has the unknown value " + std::to_string(int(d.shape));
  }
  return s->validate(d);
}

namespace detail {

std::unique_ptr<Schedule> makeSchedule(QuerySchedule schedule, const QueryScheduleDesc& desc) {
  const ScheduleDef* s = find(schedule);
  return s ? s->make(desc) : nullptr;
}

}  // namespace detail
}  // namespace logrid
