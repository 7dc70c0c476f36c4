// log-zfar: the lazy occlusion grid's zfar variant (Hey, Tobler, Purgathofer 2001, §4):
// each tile keeps the farthest depth of its pixels, a box is hidden when it lies behind
// every tile's farthest depth (or the pixels read), in any front-to-back order.
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& logZfarMethod() {
  static const MethodDef def = [] {
    MethodDef m =
        methodNamed(Method::LogZfar, "log-zfar",
                    "lazy occlusion grid, zfar variant (depth tests, any front-to-back order)");
    m.info.traversal = Traversal::FrontToBack;
    m.info.semantics = TestSemantics::Depth;
    m.info.grid = GridVariant::Zfar;
    m.info.needs.depth = true;
    m.info.takes.lookahead = m.info.takes.temporal_coherence = true;
    m.info.takes.visible_pixels = m.info.takes.row_stride = true;
    m.make_tester = lazyGridTester;
    return m;
  }();
  return def;
}

}  // namespace logrid::detail
