// ddo+log: the directional discretized occluders selected for the viewpoint are drawn
// into the depth buffer first (depth only; OccluderUse::Drawn), then log-state culls the
// hierarchy. The occluders are announced like anything drawn out of order: their tiles
// are outdated, and occlusion-state tests of boxes in front of them go by depth.
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& ddoLogMethod() {
  static const MethodDef def = [] {
    MethodDef m =
        methodLike(logStateMethod(), Method::DdoLog, "ddo+log",
                   "directional discretized occluders drawn into the depth buffer first, then "
                   "log-state");
    m.info.occluders = OccluderUse::Drawn;
    m.info.needs.occluders = true;
    return m;
  }();
  return def;
}

}  // namespace logrid::detail
