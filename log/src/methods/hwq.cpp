// hwq: one hardware occlusion query per tested box, its answer waited for at once (stop
// and wait, the baseline of the query schedules; log/src/query_hwq.cpp).
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& hwqMethod() {
  static const MethodDef def = queryMethod(
      Method::Hwq, "hwq", "one hardware occlusion query per tested box, waited for at once",
      QuerySchedule::Hwq);
  return def;
}

}  // namespace logrid::detail
