// What the hardware-occlusion-query methods share: their schedule comes from the
// schedule table (query_schedule.cpp; one file per schedule, log/src/query_*.cpp).
#include "method_def.hpp"

namespace logrid {

std::optional<QuerySchedule> querySchedule(const CullerDesc& desc) {
  const MethodInfo& info = methodInfo(desc.method);
  if (info.traversal != Traversal::Schedule) return std::nullopt;
  return info.takes.query_schedule ? desc.queries.schedule : info.schedule;
}

namespace detail {

std::unique_ptr<Schedule> makeMethodSchedule(const CullerDesc& desc, const MethodInfo&) {
  return makeSchedule(*querySchedule(desc), desc.queries);
}

std::string validateMethodSchedule(const CullerDesc& desc, const MethodInfo&) {
  return validateQuerySchedule(*querySchedule(desc), desc.queries);
}

MethodDef queryMethod(Method method, const char* name, const char* description,
                      QuerySchedule schedule) {
  MethodDef m = methodNamed(method, name, description);
  m.info.traversal = Traversal::Schedule;
  m.info.semantics = TestSemantics::Depth;
  m.info.schedule = schedule;
  m.info.needs.queries = true;
  m.make_tester = noTester;
  m.make_schedule = makeMethodSchedule;
  m.validate = validateMethodSchedule;
  return m;
}

}  // namespace detail
}  // namespace logrid
