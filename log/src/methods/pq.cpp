// pq: one pixel-level query over each tested box's whole rectangle, counting the pixels
// where it could show (the lazy grid paper's comparison, §5); no records are kept.
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& pqMethod() {
  static const MethodDef def = [] {
    MethodDef m = methodNamed(Method::Pq, "pq",
                              "one pixel-level query over each tested box's whole rectangle");
    m.info.traversal = Traversal::TwoList;
    m.info.semantics = TestSemantics::OcclusionState;
    m.info.needs.depth = true;
    m.info.takes.lookahead = m.info.takes.temporal_coherence = true;
    m.info.takes.visible_pixels = true;
    m.make_tester = [](const CullerDesc& desc, const MethodInfo&) {
      return makeRectCountTester(desc.approximation.visible_pixels);
    };
    return m;
  }();
  return def;
}

}  // namespace logrid::detail
