// log+hwq: the lazy occlusion grid as the pre-filter of hardware occlusion queries
// (query_prefilter.hpp): its records decide what they can without a read, and the boxes
// they leave undecided are queried with the schedule CullerDesc::queries.schedule names.
// The schedules draw what they find visible at once, so the grid tests by depth (zfar).
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& logHwqMethod() {
  static const MethodDef def = [] {
    MethodDef m = methodNamed(Method::LogHwq, "log+hwq",
                              "the lazy grid's records decide what they can, the rest is queried "
                              "(CullerDesc::queries.schedule)");
    m.info.traversal = Traversal::Schedule;
    m.info.semantics = TestSemantics::Depth;
    m.info.grid = GridVariant::Zfar;
    m.info.needs.depth = m.info.needs.queries = true;
    m.info.takes.query_schedule = true;
    m.make_tester = lazyGridTester;
    m.make_schedule = makeMethodSchedule;
    m.validate = validateMethodSchedule;
    return m;
  }();
  return def;
}

}  // namespace logrid::detail
