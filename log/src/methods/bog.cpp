// bog: the busy occlusion grid the lazy grid paper compares against (Hey, Tobler,
// Purgathofer 2001, §5): the same tiles and two-list order as log-state, but every tile
// under a drawn box is read right after the draw, whether a test will need it or not.
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& bogMethod() {
  static const MethodDef def = [] {
    MethodDef m = methodNamed(Method::Bog, "bog",
                              "busy occlusion grid: tiles refreshed right after each draw");
    m.info.traversal = Traversal::TwoList;
    m.info.semantics = TestSemantics::OcclusionState;
    m.info.grid = GridVariant::OcclusionState;
    m.info.needs.depth = true;
    m.info.takes.temporal_coherence = true;
    m.info.takes.visible_pixels = m.info.takes.full_fraction = m.info.takes.row_stride = true;
    m.make_tester = [](const CullerDesc& desc, const MethodInfo& info) {
      return makeGridTester(desc, *info.grid, GridRefresh::Busy);
    };
    return m;
  }();
  return def;
}

}  // namespace logrid::detail
