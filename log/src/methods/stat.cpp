// stat: statistically optimised occlusion queries (Kovalčík & Sochor 2005;
// log/src/query_stat.cpp).
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& statMethod() {
  static const MethodDef def = queryMethod(
      Method::Stat, "stat",
      "statistically optimised queries (Kovalcik & Sochor): visible nodes queried less often",
      QuerySchedule::Stat);
  return def;
}

}  // namespace logrid::detail
