// log-state: the lazy occlusion grid's occlusion-state variant with the two-list
// traversal (Hey, Tobler, Purgathofer 2001, §3): a box is hidden when every pixel of its
// rectangle holds something drawn, which the two-list order makes sound.
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& logStateMethod() {
  static const MethodDef def = [] {
    MethodDef m = methodNamed(Method::LogState, "log-state",
                              "lazy occlusion grid, occlusion-state variant (two-list traversal)");
    m.info.traversal = Traversal::TwoList;
    m.info.semantics = TestSemantics::OcclusionState;
    m.info.grid = GridVariant::OcclusionState;
    m.info.needs.depth = true;
    m.info.takes.lookahead = m.info.takes.temporal_coherence = true;
    m.info.takes.visible_pixels = m.info.takes.full_fraction = m.info.takes.row_stride = true;
    m.make_tester = lazyGridTester;
    return m;
  }();
  return def;
}

}  // namespace logrid::detail
