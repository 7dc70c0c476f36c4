// hzb: a hierarchical z-buffer (Greene, Kass, Miller 1993) kept on the CPU and updated
// from the drawn box's area after each draw (depth_pyramid.hpp), as the lazy grid paper's
// comparison (§5); tests read nothing, updates read every pixel drawn over.
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& hzbMethod() {
  static const MethodDef def = [] {
    MethodDef m =
        methodNamed(Method::Hzb, "hzb",
                    "hierarchical z-buffer, refreshed from the drawn box's area after each draw");
    m.info.traversal = Traversal::TwoList;
    m.info.semantics = TestSemantics::Depth;
    m.info.needs.depth = m.info.needs.depth_values = true;
    m.info.takes.temporal_coherence = true;
    m.make_tester = [](const CullerDesc&, const MethodInfo&) { return makePyramidTester(); };
    return m;
  }();
  return def;
}

}  // namespace logrid::detail
