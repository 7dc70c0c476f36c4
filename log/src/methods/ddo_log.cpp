// ddo+log: log-state over the hierarchy, with the directional discretized occluders
// selected for the viewpoint recorded in the grid (OccluderUse::Recorded): the cells each
// occluder quad covers entirely are hidden behind its farthest key, without a read or a
// draw (occluder_source.hpp says why the scene's own geometry then hides them). The
// depth buffer, the records and the two-list order stay log-state's: no occlusion-state
// test falls back to depth because of them.
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& ddoLogMethod() {
  static const MethodDef def = [] {
    MethodDef m =
        methodLike(logStateMethod(), Method::DdoLog, "ddo+log",
                   "log-state with the directional discretized occluders' coverage recorded "
                   "in the grid, without a read or a draw");
    m.info.occluders = OccluderUse::Recorded;
    m.info.needs.occluders = true;
    return m;
  }();
  return def;
}

}  // namespace logrid::detail
