// nohc: near-optimal hierarchical culling (Guthe, Balázs, Klein 2006;
// log/src/query_nohc.cpp): a query only where the cost model says it pays.
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& nohcMethod() {
  static const MethodDef def =
      queryMethod(Method::Nohc, "nohc",
                  "near-optimal hierarchical culling (Guthe et al.): a query only where it pays",
                  QuerySchedule::Nohc);
  return def;
}

}  // namespace logrid::detail
