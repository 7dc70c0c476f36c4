// ddo+log: the directional discretized occluders selected for the viewpoint are drawn
// into the depth buffer first (depth only; OccluderUse::Drawn), then log-state culls the
// hierarchy. The occluders are announced like anything drawn out of order: their tiles
// are outdated, and occlusion-state tests of boxes in front of them go by depth.
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& ddoLogMethod() {
  static const MethodDef def = [] {
    MethodDef m =
        methodNamed(Method::DdoLog, "ddo+log",
                    "directional discretized occluders drawn into the depth buffer first, then "
                    "log-state");
    m.info.traversal = Traversal::TwoList;
    m.info.semantics = TestSemantics::OcclusionState;
    m.info.grid = GridVariant::OcclusionState;
    m.info.occluders = OccluderUse::Drawn;
    m.info.needs.depth = m.info.needs.occluders = true;
    m.info.takes.lookahead = m.info.takes.temporal_coherence = true;
    m.info.takes.visible_pixels = m.info.takes.full_fraction = m.info.takes.row_stride = true;
    m.make_tester = lazyGridTester;
    return m;
  }();
  return def;
}

}  // namespace logrid::detail
