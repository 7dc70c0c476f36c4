// chc: coherent hierarchical culling revisited, CHC++ (Mattausch, Bittner, Wimmer 2008;
// log/src/query_chc.cpp).
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& chcMethod() {
  static const MethodDef def = queryMethod(
      Method::Chc, "chc",
      "CHC++: visible leaves drawn at once, invisible nodes queried in multi-query batches",
      QuerySchedule::Chc);
  return def;
}

}  // namespace logrid::detail
