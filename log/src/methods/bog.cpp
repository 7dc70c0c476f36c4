// bog: the busy occlusion grid the lazy grid paper compares against (Hey, Tobler,
// Purgathofer 2001, §5): the same tiles and two-list order as log-state, but every tile
// under a drawn box is read right after the draw, whether a test will need it or not.
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& bogMethod() {
  static const MethodDef def = [] {
    MethodDef m = methodLike(logStateMethod(), Method::Bog, "bog",
                             "busy occlusion grid: tiles refreshed right after each draw");
    m.info.takes.lookahead = false;  // its tiles are read after each draw, not by tests
    m.make_tester = [](const CullerDesc& desc, const MethodInfo& info) {
      return makeGridTester(desc, *info.grid, GridRefresh::Busy);
    };
    return m;
  }();
  return def;
}

}  // namespace logrid::detail
